#include "assembly/node_block_reduction.hpp"

#include <atomic>

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <string>

namespace dipc {

namespace {
// An element node pair on a block row, bucketed by row: its column node, and the key that
// orders the summation, (form index << 56) | (64e + 8a + b).
struct Item {
  std::int64_t col;
  std::uint64_t key;
};
constexpr int kFormShift = 56;
constexpr std::uint64_t kSourceMask = (std::uint64_t{1} << 32) - 1;
// Sources are 64e + 8a + b in 32 bits.
constexpr std::int64_t kMaxElements = std::int64_t{1} << 26;

// Rows are global nodes. The owned ones are contiguous and indexed directly; the others (ghost
// nodes of this rank's elements) are numbered by their rank among the distinct ones, so that no
// array spans the global node range (as in CooReduction). Slots follow the global node order:
// the ghosts below the owned range, the owned range, the ghosts above it.
struct RowSlots {
  std::int64_t dense_begin = 0, dense_end = 0;
  std::vector<std::int64_t> sparse;
  std::size_t below = 0, dense_size = 0, num_rows = 0;

  bool in_dense(std::int64_t g) const { return g >= dense_begin && g < dense_end; }
  std::size_t slot_of(std::int64_t g) const {
    if (in_dense(g)) return below + static_cast<std::size_t>(g - dense_begin);
    return static_cast<std::size_t>(std::lower_bound(sparse.begin(), sparse.end(), g) - sparse.begin()) +
           (g >= dense_end ? dense_size : 0);
  }
  std::int64_t node_of(std::size_t s) const {
    return s < below                ? sparse[s]
           : s < below + dense_size ? dense_begin + static_cast<std::int64_t>(s - below)
                                    : sparse[s - dense_size];
  }
};

void check_limits(const std::vector<NodeBlockReduction::Input>& inputs) {
  if (inputs.size() >= (std::size_t{1} << (64 - kFormShift)))
    throw std::length_error("too many element forms for the node-block reduction");
  for (const NodeBlockReduction::Input& in : inputs)
    if (in.pattern.num_elements >= kMaxElements)
      throw std::length_error("an element form has " + std::to_string(in.pattern.num_elements) +
                              " elements on one rank; the node-block map holds at most 2^26 - 1 (67,108,863) per "
                              "rank: run on more ranks");
}

RowSlots row_slots(const std::vector<NodeBlockReduction::Input>& inputs, std::int64_t owned_begin,
                   std::int64_t owned_end) {
  RowSlots r;
  r.dense_begin = owned_begin;
  r.dense_end = std::max(owned_begin, owned_end);
  for (const NodeBlockReduction::Input& in : inputs) {
    const ElementPattern& p = in.pattern;
    for (std::size_t k = 0; k < 8 * static_cast<std::size_t>(p.num_elements); ++k) {
      const std::int64_t g = p.local_to_global[p.nodes[k]];
      if (!r.in_dense(g)) r.sparse.push_back(g);
    }
  }
  std::sort(r.sparse.begin(), r.sparse.end());
  r.sparse.erase(std::unique(r.sparse.begin(), r.sparse.end()), r.sparse.end());
  r.sparse.shrink_to_fit();
  r.dense_size = static_cast<std::size_t>(r.dense_end - r.dense_begin);
  r.below = static_cast<std::size_t>(std::lower_bound(r.sparse.begin(), r.sparse.end(), r.dense_begin) -
                                     r.sparse.begin());
  r.num_rows = r.dense_size + r.sparse.size();
  return r;
}
}  // namespace

std::uint64_t NodeBlockReduction::next_id() {
  static std::atomic<std::uint64_t> made{0};
  return ++made;
}

std::vector<std::uint32_t> NodeBlockReduction::block_start_32() const {
  if (num_entries() > std::numeric_limits<std::uint32_t>::max())
    throw std::length_error("node blocks: " + std::to_string(num_entries()) +
                            " Hessian entries on one rank, more than 32-bit starts hold: run on more ranks");
  return std::vector<std::uint32_t>(block_start.begin(), block_start.end());
}

std::vector<std::uint32_t> NodeBlockReduction::row_start_32() const {
  if (num_blocks() > std::numeric_limits<std::uint32_t>::max())
    throw std::length_error("node blocks: " + std::to_string(num_blocks()) +
                            " node blocks on one rank, more than 32-bit row starts hold: run on more ranks");
  return std::vector<std::uint32_t>(row_start.begin(), row_start.end());
}

std::vector<std::uint32_t> NodeBlockReduction::block_col_32() const {
  std::vector<std::uint32_t> out(block_col.size());
  bool fits = true;
  for (std::size_t k = 0; k < block_col.size(); ++k) {
    fits = fits && static_cast<std::uint64_t>(block_col[k]) <= std::numeric_limits<std::uint32_t>::max();
    out[k] = static_cast<std::uint32_t>(block_col[k]);
  }
  if (!fits) throw std::length_error("node blocks: node ids of 2^32 or more do not fit the device's 32-bit columns");
  return out;
}

NodeBlockReduction NodeBlockReduction::build(const std::vector<Input>& inputs, std::int64_t owned_begin,
                                             std::int64_t owned_end) {
  check_limits(inputs);
  RowSlots slots = row_slots(inputs, owned_begin, owned_end);
  const std::size_t num_rows = slots.num_rows;
  const auto slot_of = [&slots](std::int64_t g) { return slots.slot_of(g); };

  // Counting sort of the element node pairs by row node: 8 per element node, filled in the
  // order form, element, row node, column node, so that each row's items come in key order.
  std::vector<std::size_t> start(num_rows + 1, 0);
  for (const Input& in : inputs) {
    const ElementPattern& p = in.pattern;
    for (std::size_t k = 0; k < 8 * static_cast<std::size_t>(p.num_elements); ++k)
      start[slot_of(p.local_to_global[p.nodes[k]]) + 1] += 8;
  }
  for (std::size_t s = 0; s < num_rows; ++s) start[s + 1] += start[s];
  LargePageVector<Item> items(start[num_rows]);
  {
    std::vector<std::size_t> next(start.begin(), start.end() - 1);
    for (std::size_t f = 0; f < inputs.size(); ++f) {
      const ElementPattern& p = inputs[f].pattern;
      for (std::int64_t e = 0; e < p.num_elements; ++e) {
        std::int64_t g[8];
        for (int a = 0; a < 8; ++a) g[a] = p.local_to_global[p.nodes[8 * e + a]];
        for (int a = 0; a < 8; ++a) {
          Item* out = items.data() + next[slot_of(g[a])];
          next[slot_of(g[a])] += 8;
          for (int b = 0; b < 8; ++b)
            out[b] = {g[b],
                      (static_cast<std::uint64_t>(f) << kFormShift) | static_cast<std::uint64_t>(64 * e + 8 * a + b)};
        }
      }
    }
  }

  NodeBlockReduction r;
  r.row_nodes.resize(num_rows);
  for (std::size_t s = 0; s < num_rows; ++s) r.row_nodes[s] = slots.node_of(s);
  r.dense_begin = slots.dense_begin, r.dense_end = slots.dense_end, r.dense_below = slots.below;
  std::vector<std::int64_t>().swap(slots.sparse);
  r.forms.resize(inputs.size());
  for (std::size_t f = 0; f < inputs.size(); ++f) {
    r.forms[f].layout = inputs[f].pattern.layout;
    r.forms[f].raw_begin = inputs[f].raw_begin;
    r.forms[f].sources.reserve(64 * static_cast<std::size_t>(inputs[f].pattern.num_elements));
  }
  // A row's items by column, ties in key order (form, then element: the summation order); each
  // run of one column is a block.
  r.row_start.reserve(num_rows + 1);
  r.row_start.push_back(0);
  std::uint64_t entries = 0;
  for (std::size_t s = 0; s < num_rows; ++s) {
    Item* b = items.data() + start[s];
    Item* e = items.data() + start[s + 1];
    std::sort(b, e, [](const Item& x, const Item& y) { return x.col < y.col || (x.col == y.col && x.key < y.key); });
    for (Item* it = b; it != e;) {
      Item* run = it;
      unsigned mask = 0;
      for (auto& form : r.forms) form.offsets.push_back(static_cast<std::uint32_t>(form.sources.size()));
      for (; it != e && it->col == run->col; ++it) {
        FormMap& form = r.forms[it->key >> kFormShift];
        mask |= element_block_mask(form.layout);
        form.sources.push_back(static_cast<std::uint32_t>(it->key & kSourceMask));
      }
      r.block_col.push_back(run->col);
      r.block_mask.push_back(static_cast<std::uint16_t>(mask));
      r.block_start.push_back(entries);
      entries += static_cast<std::uint64_t>(kBlockMaskBits[mask]);
    }
    r.row_start.push_back(r.block_col.size());
  }
  r.block_start.push_back(entries);
  for (auto& form : r.forms) form.offsets.push_back(static_cast<std::uint32_t>(form.sources.size()));
  r.block_col.shrink_to_fit();
  r.block_mask.shrink_to_fit();
  r.block_start.shrink_to_fit();
  for (auto& form : r.forms) form.offsets.shrink_to_fit();
  return r;
}

NodeBlockReduction NodeBlockReduction::build_on_device(const std::vector<Input>& inputs, std::int64_t owned_begin,
                                                       std::int64_t owned_end, device::NodeBlocks* on_device) {
  check_limits(inputs);
  const RowSlots slots = row_slots(inputs, owned_begin, owned_end);
  NodeBlockReduction r;
  r.row_nodes.resize(slots.num_rows);
  for (std::size_t s = 0; s < slots.num_rows; ++s) r.row_nodes[s] = slots.node_of(s);
  r.dense_begin = slots.dense_begin, r.dense_end = slots.dense_end, r.dense_below = slots.below;
  // Each form's element nodes as row slots, on the device.
  std::vector<device::Array<std::uint32_t>> d_slots;
  for (const Input& in : inputs) {
    const ElementPattern& p = in.pattern;
    std::vector<std::uint32_t> element_slots(8 * static_cast<std::size_t>(p.num_elements));
    for (std::size_t k = 0; k < element_slots.size(); ++k)
      element_slots[k] = static_cast<std::uint32_t>(slots.slot_of(p.local_to_global[p.nodes[k]]));
    d_slots.emplace_back("element node slots");
    d_slots.back().upload(element_slots);
  }
  std::vector<device::NodeBlockForm> forms;
  for (std::size_t f = 0; f < inputs.size(); ++f)
    forms.push_back(
        {d_slots[f].data(), static_cast<std::size_t>(inputs[f].pattern.num_elements), inputs[f].pattern.layout});
  device::Array<std::int64_t> d_row_nodes("node-block row nodes");
  d_row_nodes.upload(r.row_nodes);
  device::build_node_blocks(forms.data(), static_cast<int>(forms.size()), slots.num_rows, d_row_nodes.data(),
                            on_device);
  // The pattern comes back to the host; the forms' maps stay on the device.
  static_assert(sizeof(std::size_t) == sizeof(std::uint64_t), "row starts are downloaded as 64-bit");
  r.row_start.resize(slots.num_rows + 1);
  on_device->row_start.download(reinterpret_cast<std::uint64_t*>(r.row_start.data()));
  r.block_col.resize(on_device->num_blocks);
  r.block_mask.resize(on_device->num_blocks);
  r.block_start.resize(on_device->num_blocks + 1);
  on_device->col.download(r.block_col.data());
  on_device->mask.download(r.block_mask.data());
  on_device->start.download(r.block_start.data());
  r.forms.resize(inputs.size());
  for (std::size_t f = 0; f < inputs.size(); ++f) {
    r.forms[f].layout = inputs[f].pattern.layout;
    r.forms[f].raw_begin = inputs[f].raw_begin;
  }
  return r;
}

void NodeBlockReduction::entries(std::vector<PetscInt>* rows, std::vector<PetscInt>* cols) const {
  const std::size_t n = num_entries();
  rows->resize(n);
  cols->resize(n);
  constexpr std::int64_t kMaxDof = std::numeric_limits<PetscInt>::max();
  for (std::size_t s = 0; s + 1 < row_start.size(); ++s) {
    const std::int64_t row_node = row_nodes[s];
    for (std::size_t k = row_start[s]; k < row_start[s + 1]; ++k) {
      if (3 * std::max(row_node, block_col[k]) + 2 > kMaxDof)
        throw std::overflow_error("global dof id " + std::to_string(3 * std::max(row_node, block_col[k]) + 2) +
                                  " does not fit PETSc's " + std::to_string(8 * sizeof(PetscInt)) +
                                  "-bit PetscInt: use a PETSc configured with --with-64-bit-indices");
      for_each_entry(row_node, k, [&](std::size_t entry, std::int64_t row, std::int64_t col) {
        (*rows)[entry] = static_cast<PetscInt>(row);
        (*cols)[entry] = static_cast<PetscInt>(col);
      });
    }
  }
}

std::int64_t NodeBlockReduction::find_row(std::int64_t row_node, std::size_t* row_hint) const {
  if (row_node < 0 || row_nodes.empty()) return -1;
  if (row_node >= dense_begin && row_node < dense_end) {
    const std::size_t s = dense_below + static_cast<std::size_t>(row_node - dense_begin);
    if (row_hint) *row_hint = s;
    return static_cast<std::int64_t>(s);
  }
  auto from = row_nodes.begin();
  if (row_hint && *row_hint < row_nodes.size() && row_nodes[*row_hint] <= row_node) {
    from += static_cast<std::ptrdiff_t>(*row_hint);
    if (*from != row_node && from + 1 != row_nodes.end() && from[1] == row_node) ++from;  // the next row
  }
  const auto r = *from == row_node ? from : std::lower_bound(from, row_nodes.end(), row_node);
  if (row_hint) *row_hint = static_cast<std::size_t>(std::min(r, row_nodes.end() - 1) - row_nodes.begin());
  if (r == row_nodes.end() || *r != row_node) return -1;
  return static_cast<std::int64_t>(r - row_nodes.begin());
}

std::int64_t NodeBlockReduction::find_block(std::int64_t row_node, std::int64_t col_node, std::size_t* row_hint) const {
  if (col_node < 0) return -1;
  const std::int64_t row = find_row(row_node, row_hint);
  if (row < 0) return -1;
  const std::size_t s = static_cast<std::size_t>(row);
  const auto first = block_col.begin() + static_cast<std::ptrdiff_t>(row_start[s]);
  const auto last = block_col.begin() + static_cast<std::ptrdiff_t>(row_start[s + 1]);
  const auto c = std::lower_bound(first, last, col_node);
  if (c == last || *c != col_node) return -1;
  return static_cast<std::int64_t>(c - block_col.begin());
}

std::int64_t NodeBlockReduction::find(std::int64_t row, std::int64_t col, std::size_t* row_hint) const {
  if (row < 0 || col < 0) return -1;
  const std::int64_t b = find_block(row / 3, col / 3, row_hint);
  if (b < 0) return -1;
  const std::size_t k = static_cast<std::size_t>(b);
  const int bit = static_cast<int>(3 * (row % 3) + col % 3);
  if (!(block_mask[k] >> bit & 1u)) return -1;
  return static_cast<std::int64_t>(block_start[k]) + entry_in_block(block_mask[k], bit);
}

void NodeBlockReduction::index_elements() {
  if (num_blocks() > std::numeric_limits<std::uint32_t>::max())
    throw std::length_error("more than 2^32 - 1 node blocks on one rank: run on more ranks");
  for (FormMap& form : forms) {
    form.block_of.resize(form.sources.size());
    for (std::size_t k = 0; k + 1 < form.offsets.size(); ++k)
      for (std::uint32_t j = form.offsets[k]; j < form.offsets[k + 1]; ++j)
        form.block_of[form.sources[j]] = static_cast<std::uint32_t>(k);
    LargePageVector<std::uint32_t>().swap(form.offsets);
    LargePageVector<std::uint32_t>().swap(form.sources);
  }
}

void NodeBlockReduction::add_elements(std::size_t m, int first, int count, const double* values, double* unique) const {
  const FormMap& form = forms[m];
  const std::size_t per = static_cast<std::size_t>(element_values(form.layout));
  const unsigned form_mask = element_block_mask(form.layout);
  for (int e = 0; e < count; ++e) {
    const double* v = values + per * static_cast<std::size_t>(e);
    const std::uint32_t* blocks = form.block_of.data() + 64 * (static_cast<std::size_t>(first) + e);
    for (int ab = 0; ab < 64; ++ab) {
      const std::uint32_t k = blocks[ab];
      const unsigned mask = block_mask[k];
      double* out = unique + block_start[k];
      for (int bit = 0; bit < 9; ++bit)
        if (form_mask >> bit & 1u)
          out[entry_in_block(mask, bit)] += v[element_value_offset(form.layout, ab >> 3, bit / 3, ab & 7, bit % 3)];
    }
  }
}

void NodeBlockReduction::reduce(const double* raw, double* unique) const {
  const std::size_t nb = num_blocks();
  for (std::size_t k = 0; k < nb; ++k) {
    // Each entry's sum runs over the forms, then their sources, in order: the device kernel's
    // order (device::reduce_element_blocks).
    double sum[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
    for (const FormMap& form : forms) {
      const std::size_t per = static_cast<std::size_t>(element_values(form.layout));
      const unsigned form_mask = element_block_mask(form.layout);
      for (std::uint32_t j = form.offsets[k]; j < form.offsets[k + 1]; ++j) {
        const std::uint32_t src = form.sources[j];
        const int a = static_cast<int>(src >> 3 & 7u), b = static_cast<int>(src & 7u);
        const double* v = raw + form.raw_begin + per * (src >> 6);
        for (int bit = 0; bit < 9; ++bit)
          if (form_mask >> bit & 1u) sum[bit] += v[element_value_offset(form.layout, a, bit / 3, b, bit % 3)];
      }
    }
    double* out = unique + block_start[k];
    for (int bit = 0; bit < 9; ++bit)
      if (block_mask[k] >> bit & 1u) *out++ = sum[bit];
  }
}

}  // namespace dipc
