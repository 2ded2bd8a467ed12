#include "assembly/cuda/node_block_pattern.hpp"

#include <cub/cub.cuh>

#include <algorithm>
#include <string>

#include "assembly/cuda/element_kernels.hpp"
#include "device/cuda_check.cuh"

namespace dipc::device {

namespace {

constexpr int kThreads = 256;

// The forms' pair ranges and masks by value: form f's pairs are the global items
// [base[f], base[f + 1]).
struct FormRanges {
  std::uint32_t base[kMaxElementBlockMaps + 1];
  unsigned mask[kMaxElementBlockMaps];
  int count;
};

__device__ int form_of(const FormRanges& forms, std::uint32_t item) {
  int f = 0;
  while (f + 1 < forms.count && item >= forms.base[f + 1]) ++f;
  return f;
}

// Pair t = 64e + 8a + b of one form: key row slot * num_rows + column slot, value its global
// item number base + t (ascending in the order form, element, a, b).
__global__ void make_pairs(const std::uint32_t* __restrict__ slots, std::size_t num_pairs, std::uint64_t num_rows,
                           std::uint32_t base, std::uint64_t* __restrict__ keys, std::uint32_t* __restrict__ items) {
  const std::size_t t = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  if (t >= num_pairs) return;
  const std::size_t e = t >> 6;
  const unsigned a = (t >> 3) & 7u, b = t & 7u;
  keys[t] = static_cast<std::uint64_t>(slots[8 * e + a]) * num_rows + slots[8 * e + b];
  items[t] = base + static_cast<std::uint32_t>(t);
}

// head[i] = 1 where sorted pair i starts a block.
__global__ void mark_heads(const std::uint64_t* __restrict__ keys, std::size_t n, std::uint32_t* __restrict__ head) {
  const std::size_t i = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  if (i < n) head[i] = i == 0 || keys[i] != keys[i - 1] ? 1u : 0u;
}

// first[k]: the first sorted pair of block k (block = the exclusive count of heads before it).
__global__ void block_firsts(const std::uint32_t* __restrict__ head, const std::uint32_t* __restrict__ block_of,
                             std::size_t n, std::uint32_t* __restrict__ first) {
  const std::size_t i = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  if (i < n && head[i]) first[block_of[i]] = static_cast<std::uint32_t>(i);
}

// Per block: its row slot, global column node, mask (the union of its forms' masks) and entry
// count (for the starts' scan; the last slot, num_blocks, counts 0).
__global__ void describe_blocks(const std::uint64_t* __restrict__ keys, const std::uint32_t* __restrict__ items,
                                const std::uint32_t* __restrict__ first, std::size_t num_blocks, std::uint64_t num_rows,
                                const std::int64_t* __restrict__ slot_nodes, FormRanges forms,
                                std::uint32_t* __restrict__ row, std::int64_t* __restrict__ col,
                                std::uint16_t* __restrict__ mask, std::uint64_t* __restrict__ count) {
  const std::size_t k = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  if (k > num_blocks) return;
  if (k == num_blocks) {
    count[k] = 0;
    return;
  }
  const std::uint64_t key = keys[first[k]];
  row[k] = static_cast<std::uint32_t>(key / num_rows);
  col[k] = slot_nodes[key % num_rows];
  unsigned m = 0;
  for (std::uint32_t i = first[k]; i < first[k + 1]; ++i) m |= forms.mask[form_of(forms, items[i])];
  mask[k] = static_cast<std::uint16_t>(m);
  count[k] = static_cast<std::uint64_t>(__popc(m));
}

// row_start[r] = the first block of a row >= r (rows without blocks, such as owned nodes of no
// element, are empty).
__global__ void row_starts(const std::uint32_t* __restrict__ row, std::size_t num_blocks, std::size_t num_rows,
                           std::uint64_t* __restrict__ row_start) {
  const std::size_t r = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  if (r > num_rows) return;
  std::size_t lo = 0, hi = num_blocks;
  while (lo < hi) {
    const std::size_t mid = (lo + hi) / 2;
    if (row[mid] < r)
      lo = mid + 1;
    else
      hi = mid;
  }
  row_start[r] = lo;
}

// in_form[i] = 1 where sorted pair i belongs to form f.
__global__ void flag_form(const std::uint32_t* __restrict__ items, std::size_t n, FormRanges forms, int f,
                          std::uint32_t* __restrict__ in_form) {
  const std::size_t i = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  if (i < n) in_form[i] = form_of(forms, items[i]) == f ? 1u : 0u;
}

// Form f's sources (its pairs in sorted order, as 64e + 8a + b) and offsets (its pairs before
// each block), from the exclusive count `before` of its pairs.
__global__ void form_sources(const std::uint32_t* __restrict__ items, const std::uint32_t* __restrict__ in_form,
                             const std::uint32_t* __restrict__ before, std::size_t n, std::uint32_t base,
                             std::uint32_t* __restrict__ sources) {
  const std::size_t i = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  if (i < n && in_form[i]) sources[before[i]] = items[i] - base;
}
__global__ void form_offsets(const std::uint32_t* __restrict__ first, const std::uint32_t* __restrict__ before,
                             std::size_t num_blocks, std::uint32_t total, std::uint32_t* __restrict__ offsets) {
  const std::size_t k = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  if (k < num_blocks) offsets[k] = before[first[k]];
  if (k == num_blocks) offsets[k] = total;
}

int bits_for(std::uint64_t largest) {
  int bits = 1;
  while (bits < 64 && (largest >> bits) != 0) ++bits;
  return bits;
}

// CUB's two-call pattern: the first call sizes the scratch space, the second runs.
template <class Run>
void with_scratch(Array<unsigned char>& scratch, Run run) {
  std::size_t bytes = 0;
  DIPC_CUDA_CHECK(run(static_cast<void*>(nullptr), bytes));
  scratch.resize(std::max<std::size_t>(bytes, 1));
  DIPC_CUDA_CHECK(run(static_cast<void*>(scratch.data()), bytes));
}

std::uint32_t read_u32(const std::uint32_t* d) {
  std::uint32_t v = 0;
  copy_to_host(&v, d, sizeof v);
  return v;
}

}  // namespace

void build_node_blocks(const NodeBlockForm* forms, int num_forms, std::size_t num_rows,
                       const std::int64_t* d_slot_nodes, NodeBlocks* out) {
  if (num_forms > kMaxElementBlockMaps)
    throw DeviceError("node-block pattern: " + std::to_string(num_forms) + " element forms, at most " +
                      std::to_string(kMaxElementBlockMaps));
  FormRanges ranges{};
  ranges.count = num_forms;
  std::uint64_t n = 0;
  for (int f = 0; f < num_forms; ++f) {
    ranges.base[f] = static_cast<std::uint32_t>(n);
    ranges.mask[f] = element_block_mask(forms[f].layout);
    n += 64 * static_cast<std::uint64_t>(forms[f].num_elements);
    if (n >= (std::uint64_t{1} << 32))
      throw DeviceError("node-block pattern: more than 2^32 - 1 element node pairs on one rank: run on more ranks");
  }
  ranges.base[num_forms] = static_cast<std::uint32_t>(n);
  out->num_blocks = 0;
  out->offsets.clear();
  out->sources.clear();
  for (int f = 0; f < num_forms; ++f) {
    out->offsets.emplace_back("node-block offsets");
    out->sources.emplace_back("node-block sources");
  }
  out->row_start.resize(num_rows + 1);
  if (n == 0) {
    out->row_start.set_zero();
    out->col.resize(0), out->mask.resize(0);
    out->start.resize(1), out->start.set_zero();
    for (int f = 0; f < num_forms; ++f) out->offsets[f].resize(1), out->offsets[f].set_zero();
    return;
  }

  // The pairs, sorted stably by (row, column) over the key's significant bits.
  Array<unsigned char> scratch("node-block scratch");
  Array<std::uint64_t> sorted_keys("node-block sorted keys");
  Array<std::uint32_t> sorted_items("node-block sorted pairs");
  sorted_keys.resize(n), sorted_items.resize(n);
  {
    Array<std::uint64_t> keys("node-block pair keys");
    Array<std::uint32_t> items("node-block pairs");
    keys.resize(n), items.resize(n);
    for (int f = 0; f < num_forms; ++f) {
      const std::size_t pairs = 64 * forms[f].num_elements;
      if (pairs == 0) continue;
      make_pairs<<<blocks_for(pairs, kThreads), kThreads>>>(forms[f].d_slots, pairs, num_rows, ranges.base[f],
                                                            keys.data() + ranges.base[f],
                                                            items.data() + ranges.base[f]);
      DIPC_CUDA_CHECK_LAUNCH();
    }
    const int end_bit = bits_for(static_cast<std::uint64_t>(num_rows) * num_rows - 1);
    with_scratch(scratch, [&](void* p, std::size_t& bytes) {
      return cub::DeviceRadixSort::SortPairs(p, bytes, keys.data(), sorted_keys.data(), items.data(),
                                             sorted_items.data(), n, 0, end_bit);
    });
  }

  // Blocks: where each starts among the sorted pairs.
  Array<std::uint32_t> first("node-block firsts");
  std::uint32_t num_blocks = 0;
  {
    Array<std::uint32_t> head("node-block heads"), block_of("node-block of pair");
    head.resize(n), block_of.resize(n);
    mark_heads<<<blocks_for(n, kThreads), kThreads>>>(sorted_keys.data(), n, head.data());
    DIPC_CUDA_CHECK_LAUNCH();
    with_scratch(scratch, [&](void* p, std::size_t& bytes) {
      return cub::DeviceScan::ExclusiveSum(p, bytes, head.data(), block_of.data(), n);
    });
    num_blocks = read_u32(block_of.data() + n - 1) + read_u32(head.data() + n - 1);
    first.resize(num_blocks + std::size_t{1});
    block_firsts<<<blocks_for(n, kThreads), kThreads>>>(head.data(), block_of.data(), n, first.data());
    DIPC_CUDA_CHECK_LAUNCH();
    const auto total = static_cast<std::uint32_t>(n);
    copy_to_device(first.data() + num_blocks, &total, sizeof total);
  }
  out->num_blocks = num_blocks;

  // Each block's row, column, mask and first entry; each row's first block.
  {
    Array<std::uint32_t> row("node-block rows");
    Array<std::uint64_t> count("node-block entry counts");
    row.resize(num_blocks), count.resize(num_blocks + std::size_t{1});
    out->col.resize(num_blocks), out->mask.resize(num_blocks), out->start.resize(num_blocks + std::size_t{1});
    describe_blocks<<<blocks_for(num_blocks + std::size_t{1}, kThreads), kThreads>>>(
        sorted_keys.data(), sorted_items.data(), first.data(), num_blocks, num_rows, d_slot_nodes, ranges, row.data(),
        out->col.data(), out->mask.data(), count.data());
    DIPC_CUDA_CHECK_LAUNCH();
    with_scratch(scratch, [&](void* p, std::size_t& bytes) {
      return cub::DeviceScan::ExclusiveSum(p, bytes, count.data(), out->start.data(), num_blocks + std::size_t{1});
    });
    row_starts<<<blocks_for(num_rows + 1, kThreads), kThreads>>>(row.data(), num_blocks, num_rows,
                                                                 out->row_start.data());
    DIPC_CUDA_CHECK_LAUNCH();
  }

  // Each form's pairs per block. One form (the usual case) owns every pair, in sorted order.
  if (num_forms == 1) {
    out->sources[0].resize(n);
    copy_on_device(out->sources[0].data(), sorted_items.data(), n * sizeof(std::uint32_t));
    out->offsets[0].resize(num_blocks + std::size_t{1});
    copy_on_device(out->offsets[0].data(), first.data(), (num_blocks + std::size_t{1}) * sizeof(std::uint32_t));
    return;
  }
  Array<std::uint32_t> in_form("node-block form flags"), before("node-block form counts");
  in_form.resize(n), before.resize(n);
  for (int f = 0; f < num_forms; ++f) {
    flag_form<<<blocks_for(n, kThreads), kThreads>>>(sorted_items.data(), n, ranges, f, in_form.data());
    DIPC_CUDA_CHECK_LAUNCH();
    with_scratch(scratch, [&](void* p, std::size_t& bytes) {
      return cub::DeviceScan::ExclusiveSum(p, bytes, in_form.data(), before.data(), n);
    });
    const std::uint32_t total = read_u32(before.data() + n - 1) + read_u32(in_form.data() + n - 1);
    out->sources[f].resize(total);
    form_sources<<<blocks_for(n, kThreads), kThreads>>>(sorted_items.data(), in_form.data(), before.data(), n,
                                                        ranges.base[f], out->sources[f].data());
    DIPC_CUDA_CHECK_LAUNCH();
    out->offsets[f].resize(num_blocks + std::size_t{1});
    form_offsets<<<blocks_for(num_blocks + std::size_t{1}, kThreads), kThreads>>>(first.data(), before.data(),
                                                                                  num_blocks, total,
                                                                                  out->offsets[f].data());
    DIPC_CUDA_CHECK_LAUNCH();
  }
}

}  // namespace dipc::device
