#include "assembly/hessian_assembler.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <utility>

#include "assembly/device_matrix.hpp"
#include "logging/log_stages.hpp"
#include "options/dipc_options.hpp"
#include "threads/host_threads.hpp"

namespace dipc {

namespace {
// -dipc_direct_matrix (default on): matrices of the types DirectMatrix serves are made from the
// entries; off, every matrix goes through PETSc's COO preallocation (for comparison).
// -dipc_pattern_remap (default fit): whether a changed pattern that fits the matrix keeps it
// (hessian_assembler.hpp). docs/performance.md measures the three: on the 1M-hex stack on one
// H200, fit kept the matrix at 8 of 11 changes with the same Newton and CG counts as off, and
// "contact patterns" took 2.4 s instead of 4.1-4.5 s.
PetscErrorCode read_options(MPI_Comm comm, bool* direct, HessianAssembler::Remap* remap) {
  PetscFunctionBeginUser;
  PetscBool flag = PETSC_TRUE;
  constexpr const OptionSpec& direct_option = dipc_option("-dipc_direct_matrix");
  constexpr const OptionSpec& remap_option = dipc_option("-dipc_pattern_remap");
  // PetscOptionsEnum's list: the choices in the order of the enum, its name, its prefix, null.
  static_assert(remap_option.choices.count == 3, "the choices are the enum's values");
  const char* const remap_names[] = {remap_option.choices.words[0],
                                     remap_option.choices.words[1],
                                     remap_option.choices.words[2],
                                     "PatternRemap",
                                     "",
                                     nullptr};
  PetscEnum choice = static_cast<PetscEnum>(HessianAssembler::Remap::fit);
  PetscOptionsBegin(comm, nullptr, "dipc Hessian matrix", "Mat");
  PetscCall(PetscOptionsBool(direct_option.name, direct_option.help, direct_option.manual, flag, &flag, nullptr));
  PetscCall(PetscOptionsEnum(remap_option.name, remap_option.help, remap_option.manual, remap_names, choice, &choice,
                             nullptr));
  PetscOptionsEnd();
  *direct = flag == PETSC_TRUE;
  *remap = static_cast<HessianAssembler::Remap>(choice);
  PetscFunctionReturn(0);
}
}  // namespace

PetscErrorCode HessianAssembler::setup(const Dofs& dofs, std::vector<Term> terms) {
  PetscFunctionBeginUser;
  dofs_ = dofs;
  terms_ = std::move(terms);
  for (const auto& term : terms_) {
    any_device_ = any_device_ || term.space == MemorySpace::device;
    pattern_versions_.push_back(term.pattern->pattern_version());
  }
  PetscCall(read_options(dofs_.comm, &direct_matrix_allowed_, &remap_));
  PetscFunctionReturn(0);
}

PetscErrorCode HessianAssembler::create_matrix(Mat* J) {
  PetscFunctionBeginUser;
  const PetscInt num_owned_dofs = 3 * dofs_.num_owned_nodes;
  PetscCall(MatCreate(dofs_.comm, J));
  PetscCall(MatSetSizes(*J, num_owned_dofs, num_owned_dofs, PETSC_DETERMINE, PETSC_DETERMINE));
  PetscCall(MatSetBlockSize(*J, 3));
  PetscCall(MatSetType(*J, MATAIJ));
  PetscCall(MatSetFromOptions(*J));
  J_ = *J;
  PetscCall(rebuild_pattern(true));
  *J = J_;  // a direct matrix replaced the template
  PetscCall(MatSetOption(*J, MAT_SPD, PETSC_TRUE));
  PetscFunctionReturn(0);
}

bool HessianAssembler::pattern_changed() const {
  for (std::size_t t = 0; t < terms_.size(); ++t)
    if (terms_[t].pattern->pattern_version() != pattern_versions_[t]) return true;
  return false;
}

PetscErrorCode HessianAssembler::update_patterns(const double* x, const double* x_device, bool* new_matrix) {
  PetscFunctionBeginUser;
  for (auto& term : terms_) term.pattern->update_pattern(x, x_device);
  int local = pattern_changed() ? 1 : 0, any = 0;
  PetscCallMPI(MPI_Allreduce(&local, &any, 1, MPI_INT, MPI_MAX, dofs_.comm));
  *new_matrix = any != 0 && remap_ == Remap::off;
  // require_exact_pattern(): the same on every rank (a remap is collective).
  const bool exact = exact_next_;
  exact_next_ = false;
  if (exact) *new_matrix = any != 0 || !matrix_exact_;
  if (!any || *new_matrix) {
    awaiting_rebuild_ = *new_matrix;
    PetscFunctionReturn(0);
  }
  // Only the changing terms' patterns change: map them onto the matrix's entries where they fit
  // on every rank, else the caller makes a new matrix (whose pattern maps them again).
  PetscCall(PetscLogEventBegin(log_events().pattern_remap, 0, 0, 0, 0));
  bool fits = true;
  if (local) {
    PetscCall(gather_changing_part(&groups_));
    PetscCall(map_changing_part(groups_, true, &fits));
  }
  int all_fit = fits ? 1 : 0;
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &all_fit, 1, MPI_INT, MPI_MIN, dofs_.comm));
  *new_matrix = all_fit == 0;
  awaiting_rebuild_ = *new_matrix;
  if (!*new_matrix) {
    // A rank whose own patterns kept still keeps its raw layout and maps (the targets it sent
    // to the device are the ones it has): only the ranks that mapped anew size and send theirs.
    if (local) size_raw_values();
    ++remaps_;
    matrix_exact_ = false;
  }
  PetscCall(PetscLogEventEnd(log_events().pattern_remap, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

PetscErrorCode HessianAssembler::build_element_part() {
  PetscFunctionBeginUser;
  // The element terms' values come first in the raw array, so that their offsets (and the map's)
  // stay put when the other terms' patterns change; their patterns never do.
  std::vector<NodeBlockReduction::Input> inputs;
  term_begin_.assign(terms_.size(), 0);
  term_size_.assign(terms_.size(), 0);
  element_map_.assign(terms_.size(), -1);
  bool all_host = true, all_device = true;
  std::size_t raw = 0;
  for (std::size_t t = 0; t < terms_.size(); ++t) {
    ElementPattern pattern;
    if (!terms_[t].pattern->element_pattern(&pattern)) continue;
    PetscCheck(!terms_[t].pattern->pattern_may_change(), PETSC_COMM_SELF, PETSC_ERR_PLIB,
               "form %s gives node blocks but says its pattern may change", terms_[t].name.c_str());
    element_map_[t] = static_cast<int>(inputs.size());
    all_host = all_host && terms_[t].space == MemorySpace::host;
    all_device = all_device && terms_[t].space == MemorySpace::device;
    term_begin_[t] = raw;
    term_size_[t] = static_cast<std::size_t>(element_values(pattern.layout)) *
                    static_cast<std::size_t>(pattern.num_elements);
    inputs.push_back({pattern, raw});
    raw += term_size_[t];
  }
  num_element_raw_ = raw;
  // Element terms that run where the matrix is sum their values element chunk by chunk there
  // (no array of all of them: 576 values per hex). Otherwise their values cross in one block.
  const bool device_sums = device_matrix_ && !inputs.empty();
  const bool chunked = !inputs.empty() && (device_matrix_ ? all_device : all_host);
  const std::int64_t owned_end = dofs_.node_offset + dofs_.num_owned_nodes;
  PetscCall(elements_.build(inputs, device_sums, chunked, dofs_.node_offset, owned_end));
  PetscFunctionReturn(0);
}

namespace {
// The COO patterns of the terms t with pick(t) (the others get none), in term order, into
// (rows, cols) from their end; each term's start in the raw values is raw_begin + its offset.
template <class Pick>
void gather_coo_patterns(const std::vector<HessianAssembler::Term>& terms, Pick&& pick, std::size_t raw_begin,
                         std::vector<std::size_t>* term_begin, std::vector<std::size_t>* term_size,
                         std::vector<PetscInt>* rows, std::vector<PetscInt>* cols) {
  std::vector<PetscInt> term_rows, term_cols;
  for (std::size_t t = 0; t < terms.size(); ++t) {
    if (!pick(t)) continue;
    terms[t].pattern->coo_pattern(&term_rows, &term_cols);
    (*term_begin)[t] = raw_begin + rows->size();
    (*term_size)[t] = term_rows.size();
    rows->insert(rows->end(), term_rows.begin(), term_rows.end());
    cols->insert(cols->end(), term_cols.begin(), term_cols.end());
  }
}
}  // namespace

PetscErrorCode HessianAssembler::build_fixed_part() {
  PetscFunctionBeginUser;
  // The COO terms whose pattern never changes (the lumped mass) after the element terms' values,
  // then the Dirichlet diagonal.
  const std::vector<char>& prescribed = *dofs_.prescribed;
  const PetscInt num_owned_dofs = 3 * dofs_.num_owned_nodes;
  std::vector<PetscInt> rows, cols;
  gather_coo_patterns(
      terms_, [&](std::size_t t) { return element_map_[t] < 0 && !changing(t); }, num_element_raw_, &term_begin_,
      &term_size_, &rows, &cols);
  // Diagonal entries of the owned prescribed dofs: in the pattern, so that kinematic nodes
  // (no element of theirs is assembled) get one; their value is set by the elimination.
  dirichlet_raw_begin_ = num_element_raw_ + rows.size();
  const PetscInt owned_begin = static_cast<PetscInt>(3 * dofs_.node_offset);
  for (PetscInt k = 0; k < num_owned_dofs; ++k)
    if (prescribed[k]) {
      rows.push_back(owned_begin + k);
      cols.push_back(owned_begin + k);
    }
  changing_raw_begin_ = num_element_raw_ + rows.size();
  PetscCall(fixed_.build(rows.data(), cols.data(), rows.size(), owned_begin, owned_begin + num_owned_dofs));
  const NodeBlockReduction& blocks = elements_.blocks();
  fixed_extra_rows_.clear(), fixed_extra_cols_.clear();
  fixed_.place([&](PetscInt row, PetscInt col, std::size_t* hint) { return blocks.find(row, col, hint); },
               blocks.num_entries(), &fixed_extra_rows_, &fixed_extra_cols_);
  if (device_matrix_) {
    d_extra_rows_.upload(std::vector<std::int64_t>(fixed_extra_rows_.begin(), fixed_extra_rows_.end()));
    d_extra_cols_.upload(std::vector<std::int64_t>(fixed_extra_cols_.begin(), fixed_extra_cols_.end()));
  }
  PetscFunctionReturn(0);
}

BlockEntries HessianAssembler::block_entries() const {
  return {&elements_.blocks(), &reserve_, &fixed_extra_rows_, &fixed_extra_cols_};
}

bool HessianAssembler::device_entry_index(device::BlockEntryIndex* index, bool with_reserve) const {
  if (!device_matrix_ || !elements_.device_index(index) || (with_reserve && !reserve_.device_index(index)))
    return false;
  index->num_extra = fixed_extra_rows_.size();
  index->extra_row = d_extra_rows_.data();
  index->extra_col = d_extra_cols_.data();
  index->extra_first = static_cast<std::uint32_t>(elements_.blocks().num_entries());
  return static_cast<std::uint64_t>(elements_.blocks().num_entries()) < 0xffffffffu;
}

PetscErrorCode HessianAssembler::gather_changing_part(std::vector<NodeGroup>* groups) {
  PetscFunctionBeginUser;
  EventScope event(log_events().pattern_groups);
  groups->clear();
  std::vector<NodeGroup>& term_groups = term_groups_;
  std::size_t raw = changing_raw_begin_;
  for (std::size_t t = 0; t < terms_.size(); ++t) {
    if (element_map_[t] >= 0 || !changing(t)) continue;
    PetscCheck(terms_[t].pattern->node_groups(&term_groups), PETSC_COMM_SELF, PETSC_ERR_PLIB,
               "form %s says its pattern may change but gives no node groups", terms_[t].name.c_str());
    term_begin_[t] = raw;
    term_size_[t] = 0;
    for (const NodeGroup& g : term_groups) term_size_[t] += node_group_values(g.count);
    raw += term_size_[t];
    groups->insert(groups->end(), term_groups.begin(), term_groups.end());
  }
  for (std::size_t t = 0; t < terms_.size(); ++t) pattern_versions_[t] = terms_[t].pattern->pattern_version();
  num_raw_entries_ = raw;
  PetscFunctionReturn(0);
}

void HessianAssembler::build_reserve(const std::vector<NodeGroup>& groups) {
  EventScope event(log_events().pattern_reserve);
  const std::size_t first = elements_.blocks().num_entries() + fixed_extra_rows_.size();
  // A device matrix: the groups' node pairs are sorted on the device (node ids below 2^32, as
  // its blocks' columns are), and the reserve stays there for the lookups and the matrix's rows.
  device::BlockEntryIndex index;
  const bool nodes_fit = std::all_of(groups.begin(), groups.end(), [](const NodeGroup& g) {
    return std::all_of(g.node.begin(), g.node.begin() + g.count,
                       [](std::int64_t n) { return n >= 0 && n <= std::int64_t{0xffffffff}; });
  });
  if (remap_ != Remap::candidates && nodes_fit && device_entry_index(&index, false)) {
    std::vector<std::int64_t> rows, cols;
    std::vector<std::uint16_t> masks;
    device::reserve_node_groups(node_group_views(groups), groups.size(), index, &rows, &cols, &masks);
    reserve_.assign(rows, cols, masks, elements_.blocks(), first);
    reserve_.upload();
    return;
  }
  // The changing terms' current groups' node blocks (16 per contact pair) and, with
  // -dipc_pattern_remap candidates, their reserved blocks. Each host thread takes the blocks
  // whose row node falls in its share of the row nodes' range, from all of them, and sorts and
  // deduplicates them: joined in thread order, they are sorted and distinct.
  std::vector<ReservedBlocks::NodePair> candidates;
  if (remap_ == Remap::candidates)
    for (std::size_t t = 0; t < terms_.size(); ++t)
      if (changing(t) && element_map_[t] < 0) terms_[t].pattern->reserved_blocks(&candidates);
  std::int64_t lo = std::numeric_limits<std::int64_t>::max(), hi = std::numeric_limits<std::int64_t>::min();
  for (const NodeGroup& g : groups)
    for (int a = 0; a < g.count; ++a) lo = std::min(lo, g.node[a]), hi = std::max(hi, g.node[a]);
  for (const ReservedBlocks::NodePair& pair : candidates) lo = std::min(lo, pair[0]), hi = std::max(hi, pair[0]);
  if (hi < lo) lo = 0, hi = -1;  // no blocks: one empty range
  const NodeBlockReduction& element_blocks = elements_.blocks();
  const std::size_t ranges = static_cast<std::size_t>(host_threads());
  std::vector<ReservedBlocks::NodePair> node_pairs = parallel_collect<ReservedBlocks::NodePair>(
      ranges,
      [&](std::size_t r0, std::size_t r1, std::vector<ReservedBlocks::NodePair>& out) {
        const std::int64_t first = split_point(lo, hi + 1, r0, ranges), last = split_point(lo, hi + 1, r1, ranges);
        // Blocks the elements hold whole need no reserve (about half of a contact pair's 16: the
        // diagonal ones and those within one body's triangle or edge); leaving them out here
        // halves the sort below.
        std::size_t hint = 0;
        const auto needs_reserve = [&](std::int64_t row_node, std::int64_t col_node) {
          const std::int64_t k = element_blocks.find_block(row_node, col_node, &hint);
          return k < 0 || element_blocks.block_mask[static_cast<std::size_t>(k)] != 0x1ffu;
        };
        for (const NodeGroup& g : groups)
          for (int a = 0; a < g.count; ++a) {
            if (g.node[a] < first || g.node[a] >= last) continue;
            for (int b = 0; b < g.count; ++b)
              if (needs_reserve(g.node[a], g.node[b])) out.push_back({g.node[a], g.node[b]});
          }
        for (const ReservedBlocks::NodePair& pair : candidates)
          if (pair[0] >= first && pair[0] < last && needs_reserve(pair[0], pair[1])) out.push_back(pair);
        std::sort(out.begin(), out.end());
        out.erase(std::unique(out.begin(), out.end()), out.end());
      },
      1);
  std::vector<ReservedBlocks::NodePair>().swap(candidates);
  const BlockEntries entries = block_entries();
  reserve_.build(
      node_pairs, elements_.blocks(), [&](PetscInt row, PetscInt col) { return entries.find_extra(row, col) >= 0; },
      first);
  // Where the values are summed on the device, the changing terms' lookups run there.
  if (device_matrix_) reserve_.upload();
}

PetscErrorCode HessianAssembler::map_changing_part(const std::vector<NodeGroup>& groups, bool trial, bool* fits) {
  PetscFunctionBeginUser;
  EventScope event(log_events().pattern_map);
  std::size_t missing = 0;
  try {
    device::BlockEntryIndex index;
    if (device_entry_index(&index, true)) {
      // The device looks every block up (a trial too: it does not stop at the first missing).
      const std::size_t entries = elements_.blocks().num_entries() + fixed_extra_rows_.size() + reserve_.num_entries();
      missing = changing_.build_on_device(groups, index, entries);
    } else {
      const BlockEntries entries = block_entries();
      missing = changing_.build(
          groups,
          [&](std::int64_t row_node, std::int64_t col_node, std::size_t* hint, std::int64_t entry[9]) {
            entries.find(row_node, col_node, hint, entry);
          },
          trial);
    }
  } catch (const std::length_error& e) {
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_SUP, "%s", e.what());
  }
  *fits = missing == 0;
  PetscFunctionReturn(0);
}

void HessianAssembler::size_raw_values() {
  EventScope event(log_events().pattern_device);
  if (device_matrix_)
    LargePageVector<PetscScalar>().swap(values_);
  else
    values_.assign(num_raw_entries_ - raw_offset(), 0.0);
  if (any_device_) {
    d_values_.resize(num_raw_entries_ - raw_offset());
    // The Dirichlet diagonal's raw values are summed, then overwritten by the elimination:
    // zeroed, so that no uninitialised memory is read.
    if (changing_raw_begin_ > dirichlet_raw_begin_)
      device::zero(d_values_.data() + (dirichlet_raw_begin_ - raw_offset()),
                   (changing_raw_begin_ - dirichlet_raw_begin_) * sizeof(double));
  }
  // The maps go to the device where the values are summed there (device terms and a device
  // matrix), and then leave the host.
  if (device_matrix_) changing_.keep_on_device();
}

PetscErrorCode HessianAssembler::rebuild_pattern(bool template_matrix) {
  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(log_events().coo_reduction, 0, 0, 0, 0));
  device_matrix_ = any_device_ && matrix_on_device(J_);
  // Host AIJ, and hypre on the device when the values are summed there, are made from the
  // entries directly (direct_matrix.hpp); other types and -dipc_direct_matrix 0 take PETSc's
  // COO path.
  direct_kind_ = direct_matrix_allowed_ ? DirectMatrix::kind_of(J_) : DirectMatrix::Kind::coo;
  if (direct_kind_ == DirectMatrix::Kind::device_hypre && !device_matrix_) direct_kind_ = DirectMatrix::Kind::coo;
  if (!elements_.built()) {
    PetscCall(PetscLogEventBegin(log_events().node_blocks, 0, 0, 0, 0));
    PetscCall(build_element_part());
    PetscCall(PetscLogEventEnd(log_events().node_blocks, 0, 0, 0, 0));
  }
  // The fixed part's pattern changes only with the owned Dirichlet dofs (its Dirichlet diagonal);
  // it is made again then, or for a matrix in the other memory space.
  const std::vector<char> owned_prescribed(dofs_.prescribed->begin(),
                                           dofs_.prescribed->begin() + 3 * dofs_.num_owned_nodes);
  const bool new_fixed = !fixed_built_ || fixed_on_device_ != device_matrix_ || owned_prescribed != fixed_prescribed_;
  if (new_fixed) {
    PetscCall(build_fixed_part());
    fixed_built_ = true;
    fixed_on_device_ = device_matrix_;
    fixed_prescribed_ = owned_prescribed;
  }
  bool fits;
  {
    PetscCall(gather_changing_part(&groups_));
    build_reserve(groups_);
    PetscCall(map_changing_part(groups_, false, &fits));
  }
  awaiting_rebuild_ = false;
  matrix_exact_ = true;
  PetscCheck(fits, PETSC_COMM_SELF, PETSC_ERR_PLIB, "the changing Hessian terms' entries are not all in their reserve");

  // The matrix's entries: the element blocks', the fixed part's that no block holds, the reserve.
  const NodeBlockReduction& blocks = elements_.blocks();
  num_unique_ = blocks.num_entries() + fixed_extra_rows_.size() + reserve_.num_entries();
  // PETSc's AIJ matrices count a rank's nonzeros in PetscInt (row offsets).
  PetscCheck(num_unique_ <= static_cast<std::size_t>(PETSC_MAX_INT), PETSC_COMM_SELF, PETSC_ERR_SUP,
             "this rank's Hessian has %zu nonzeros, more than PETSc's %d-bit PetscInt holds: run on more ranks, or "
             "use a PETSc configured with --with-64-bit-indices",
             num_unique_, static_cast<int>(8 * sizeof(PetscInt)));
  const PetscInt owned_begin = static_cast<PetscInt>(3 * dofs_.node_offset);
  dirichlet_.find(blocks, fixed_extra_rows_, fixed_extra_cols_, reserve_, *dofs_.local_to_global, *dofs_.prescribed,
                  owned_begin, owned_begin + 3 * dofs_.num_owned_nodes);

  size_raw_values();
  // The other maps go to the device too; the blocks' layout stays for the next pattern change.
  if (device_matrix_) {
    elements_.keep_on_device();
    if (new_fixed) fixed_.keep_on_device();
    dirichlet_.keep_on_device();
  }
  PetscCall(PetscLogEventEnd(log_events().coo_reduction, 0, 0, 0, 0));
  PetscCall(make_matrix(template_matrix));
  PetscFunctionReturn(0);
}

PetscErrorCode HessianAssembler::make_matrix(bool template_matrix) {
  PetscFunctionBeginUser;
  if (direct_kind_ == DirectMatrix::Kind::coo) {
    // PETSc's COO path takes every entry as a (row, col) pair; it may reorder the index arrays it
    // is given and keeps its own copy.
    std::vector<PetscInt> unique_rows, unique_cols;
    try {
      elements_.blocks().entries(&unique_rows, &unique_cols);
    } catch (const std::overflow_error& e) {
      SETERRQ(PETSC_COMM_SELF, PETSC_ERR_SUP, "%s", e.what());
    }
    unique_rows.insert(unique_rows.end(), fixed_extra_rows_.begin(), fixed_extra_rows_.end());
    unique_cols.insert(unique_cols.end(), fixed_extra_cols_.begin(), fixed_extra_cols_.end());
    reserve_.entries(&unique_rows, &unique_cols);
    PetscCall(MatSetPreallocationCOO(J_, static_cast<PetscCount>(num_unique_), unique_rows.data(), unique_cols.data()));
  } else {
    // A new matrix of the entries; it replaces the template create_matrix() made, or the
    // contents of the matrix in use (whose handle the solvers hold).
    PetscCall(PetscLogEventBegin(log_events().direct_matrix, 0, 0, 0, 0));
    Mat fresh;
    direct_.share_blocks(elements_.blocks().id, {elements_.device_masks(), elements_.device_starts(),
                                                 elements_.device_row_starts(), elements_.device_cols()});
    PetscCall(direct_.create(J_, direct_kind_, &elements_.blocks(), &reserve_, fixed_extra_rows_.data(),
                             fixed_extra_cols_.data(), fixed_extra_rows_.size(), &fresh));
    if (template_matrix) {
      PetscCall(MatDestroy(&J_));
      J_ = fresh;
    } else {
      PetscCall(MatHeaderReplace(J_, &fresh));
    }
    PetscCall(PetscLogEventEnd(log_events().direct_matrix, 0, 0, 0, 0));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode HessianAssembler::begin_values() {
  PetscFunctionBeginUser;
  // Values go to the device only where both the matrix and some terms are there.
  const bool on_device = matrix_on_device(J_) && any_device_;
  PetscCheck(on_device == device_matrix_, PETSC_COMM_SELF, PETSC_ERR_PLIB,
             "Hessian requested into a matrix in another memory space than the pattern's");
  PetscCheck(!awaiting_rebuild_, PETSC_COMM_SELF, PETSC_ERR_PLIB,
             "Hessian requested before the new matrix that update_patterns() asked for");
  PetscCheck(!elements_.chunked() || elements_.sums_on_device() == device_matrix_, PETSC_COMM_SELF, PETSC_ERR_PLIB,
             "the element terms' values are summed chunk by chunk in another memory space than the matrix's");
  // Chunks add onto the entries from 0.
  if (elements_.chunked() && device_matrix_) {
    d_unique_values_.resize(num_unique_);
    device::zero(d_unique_values_.data(), num_unique_ * sizeof(double));
  } else if (elements_.chunked()) {
    unique_values_.assign(num_unique_, 0.0);
  }
  PetscFunctionReturn(0);
}

bool HessianAssembler::add_element_chunks(std::size_t t, const double* x) {
  double* unique = device_matrix_ ? d_unique_values_.data() : unique_values_.data();
  return elements_.add_chunks(static_cast<std::size_t>(element_map_[t]), *terms_[t].pattern, x, unique);
}

double* HessianAssembler::values_for(std::size_t t) {
  // A term evaluated away from the matrix writes its block where it runs, and the block crosses
  // once (values_written): device terms into d_values_ (sized whenever there are device terms),
  // host terms into host_block_.
  // Both arrays start after the element part when that is summed chunk by chunk.
  if (terms_[t].space == MemorySpace::device) return d_values_.data() + (term_begin_[t] - raw_offset());
  if (device_matrix_) {
    host_block_.resize(term_size_[t]);
    return host_block_.data();
  }
  return values_.data() + (term_begin_[t] - raw_offset());
}

void HessianAssembler::values_written(std::size_t t) {
  const bool on_device = terms_[t].space == MemorySpace::device;
  const std::size_t begin = term_begin_[t], bytes = term_size_[t] * sizeof(double);
  if (on_device == device_matrix_ || bytes == 0) return;
  if (on_device)
    device::copy_to_host(values_.data() + (begin - raw_offset()), d_values_.data() + (begin - raw_offset()), bytes);
  else
    device::copy_to_device(d_values_.data() + (begin - raw_offset()), host_block_.data(), bytes);
}

PetscErrorCode HessianAssembler::insert_values() {
  PetscFunctionBeginUser;
  double* const unique = sum_values();
  if (direct_kind_ == DirectMatrix::Kind::coo)
    PetscCall(MatSetValuesCOO(J_, unique, INSERT_VALUES));
  else
    PetscCall(direct_.set_values(J_, unique));
  PetscFunctionReturn(0);
}

double* HessianAssembler::sum_values() {
  // Per entry: the element part's sum, then the fixed part's, then the changing part's (the
  // entries after the blocks start from 0), then the Dirichlet elimination; the same order on
  // the host and on the device.
  const std::size_t num_block_entries = elements_.blocks().num_entries();
  const std::size_t num_extra = num_unique_ - num_block_entries;
  if (device_matrix_) {
    d_unique_values_.resize(num_unique_);
    double* unique = d_unique_values_.data();
    // Nothing when chunked: add_element_chunks summed them onto entries zeroed by begin_values.
    elements_.reduce_on_device(d_values_.data(), unique);
    if (num_extra > 0 && !elements_.chunked()) device::zero(unique + num_block_entries, num_extra * sizeof(double));
    fixed_.add_on_device(d_values_.data() + (num_element_raw_ - raw_offset()), unique);
    changing_.add_on_device(d_values_.data() + (changing_raw_begin_ - raw_offset()), unique);
    dirichlet_.apply_on_device(unique);
    return unique;
  }
  unique_values_.resize(num_unique_);
  double* unique = unique_values_.data();
  elements_.reduce(values_.data(), unique);  // nothing when chunked: add_element_chunks summed them
  if (!elements_.chunked()) std::fill(unique + num_block_entries, unique + num_unique_, 0.0);
  fixed_.add(values_.data() + (num_element_raw_ - raw_offset()), unique);
  changing_.add(values_.data() + (changing_raw_begin_ - raw_offset()), unique);
  dirichlet_.apply(unique);
  return unique;
}

}  // namespace dipc
