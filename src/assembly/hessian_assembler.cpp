#include "assembly/hessian_assembler.hpp"

#include <stdexcept>
#include <utility>

#include "assembly/device_matrix.hpp"
#include "logging/log_stages.hpp"
#include "options/dipc_options.hpp"

namespace dipc {

namespace {
// -dipc_direct_matrix (default on): matrices of the types DirectMatrix serves are made from the
// entries; off, every matrix goes through PETSc's COO preallocation (for comparison).
PetscErrorCode read_direct_matrix(MPI_Comm comm, bool* direct) {
  PetscFunctionBeginUser;
  PetscBool flag = PETSC_TRUE;
  PetscOptionsBegin(comm, nullptr, "dipc Hessian matrix", "Mat");
  constexpr const OptionSpec& option = dipc_option("-dipc_direct_matrix");
  PetscCall(PetscOptionsBool(option.name, option.help, option.manual, flag, &flag, nullptr));
  PetscOptionsEnd();
  *direct = flag == PETSC_TRUE;
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
  PetscCall(read_direct_matrix(dofs_.comm, &direct_matrix_allowed_));
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

PetscErrorCode HessianAssembler::update_patterns(const double* x, bool* changed) {
  PetscFunctionBeginUser;
  for (auto& term : terms_) term.pattern->update_pattern(x);
  int local = pattern_changed() ? 1 : 0, any = 0;
  PetscCallMPI(MPI_Allreduce(&local, &any, 1, MPI_INT, MPI_MAX, dofs_.comm));
  *changed = any != 0;
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
  bool all_host = true;
  std::size_t raw = 0;
  for (std::size_t t = 0; t < terms_.size(); ++t) {
    ElementPattern pattern;
    if (!terms_[t].pattern->element_pattern(&pattern)) continue;
    PetscCheck(!terms_[t].pattern->pattern_may_change(), PETSC_COMM_SELF, PETSC_ERR_PLIB,
               "form %s gives node blocks but says its pattern may change", terms_[t].name.c_str());
    element_map_[t] = static_cast<int>(inputs.size());
    all_host = all_host && terms_[t].space == MemorySpace::host;
    term_begin_[t] = raw;
    term_size_[t] = static_cast<std::size_t>(element_values(pattern.layout)) *
                    static_cast<std::size_t>(pattern.num_elements);
    inputs.push_back({pattern, raw});
    raw += term_size_[t];
  }
  num_element_raw_ = raw;
  // A host matrix of host element terms sums their values element chunk by chunk.
  const bool device_sums = device_matrix_ && !inputs.empty();
  const bool chunked = !inputs.empty() && all_host && !device_matrix_;
  const std::int64_t owned_end = dofs_.node_offset + dofs_.num_owned_nodes;
  PetscCall(elements_.build(inputs, device_sums, chunked, dofs_.node_offset, owned_end));
  PetscFunctionReturn(0);
}

PetscErrorCode HessianAssembler::build_coo_part() {
  PetscFunctionBeginUser;
  // The other terms' raw COO lists (contact, friction, the lumped mass: small, or changing with
  // the active set) after the element terms' values, then the Dirichlet diagonal.
  const std::vector<char>& prescribed = *dofs_.prescribed;
  const PetscInt num_owned_dofs = 3 * dofs_.num_owned_nodes;
  std::vector<PetscInt> rows, cols;
  {
    std::vector<std::vector<PetscInt>> term_rows(terms_.size()), term_cols(terms_.size());
    std::size_t total = 0;
    for (std::size_t t = 0; t < terms_.size(); ++t)
      if (element_map_[t] < 0) {
        terms_[t].pattern->coo_pattern(&term_rows[t], &term_cols[t]);
        total += term_rows[t].size();
      }
    for (PetscInt k = 0; k < num_owned_dofs; ++k) total += prescribed[k] ? 1 : 0;
    rows.reserve(total), cols.reserve(total);
    pattern_versions_.clear();
    for (std::size_t t = 0; t < terms_.size(); ++t) {
      pattern_versions_.push_back(terms_[t].pattern->pattern_version());
      if (element_map_[t] >= 0) continue;
      term_begin_[t] = num_element_raw_ + rows.size();
      term_size_[t] = term_rows[t].size();
      rows.insert(rows.end(), term_rows[t].begin(), term_rows[t].end());
      cols.insert(cols.end(), term_cols[t].begin(), term_cols[t].end());
    }
  }
  // Diagonal entries of the owned prescribed dofs: in the pattern, so that kinematic nodes
  // (no element of theirs is assembled) get one; their value is set by the elimination.
  dirichlet_raw_begin_ = num_element_raw_ + rows.size();
  const PetscInt owned_begin = static_cast<PetscInt>(3 * dofs_.node_offset);
  for (PetscInt k = 0; k < num_owned_dofs; ++k)
    if (prescribed[k]) {
      rows.push_back(owned_begin + k);
      cols.push_back(owned_begin + k);
    }
  num_raw_entries_ = num_element_raw_ + rows.size();
  PetscCall(others_.build(rows.data(), cols.data(), rows.size(), owned_begin, owned_begin + num_owned_dofs));
  PetscFunctionReturn(0);
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
  PetscCall(build_coo_part());

  // The matrix's entries: the element blocks', then those of the COO part that no block holds.
  const NodeBlockReduction& blocks = elements_.blocks();
  std::vector<PetscInt> extra_rows, extra_cols;
  others_.place(blocks, &extra_rows, &extra_cols);
  num_unique_ = blocks.num_entries() + extra_rows.size();
  // PETSc's AIJ matrices count a rank's nonzeros in PetscInt (row offsets).
  PetscCheck(num_unique_ <= static_cast<std::size_t>(PETSC_MAX_INT), PETSC_COMM_SELF, PETSC_ERR_SUP,
             "this rank's Hessian has %zu nonzeros, more than PETSc's %d-bit PetscInt holds: run on more ranks, or "
             "use a PETSc configured with --with-64-bit-indices",
             num_unique_, static_cast<int>(8 * sizeof(PetscInt)));
  const PetscInt owned_begin = static_cast<PetscInt>(3 * dofs_.node_offset);
  dirichlet_.find(blocks, extra_rows, extra_cols, *dofs_.local_to_global, *dofs_.prescribed, owned_begin,
                  owned_begin + 3 * dofs_.num_owned_nodes);

  if (device_matrix_)
    LargePageVector<PetscScalar>().swap(values_);
  else
    values_.assign(num_raw_entries_ - host_raw_offset(), 0.0);
  if (any_device_) {
    d_values_.resize(num_raw_entries_);
    // The Dirichlet diagonal's raw values are summed, then overwritten by the elimination:
    // zeroed once, so that no uninitialised memory is read.
    if (num_raw_entries_ > dirichlet_raw_begin_)
      device::zero(d_values_.data() + dirichlet_raw_begin_, (num_raw_entries_ - dirichlet_raw_begin_) * sizeof(double));
  }
  // The maps go to the device where the values are summed there (device terms and a device
  // matrix), and then leave the host; the blocks' layout stays for the next pattern change.
  if (device_matrix_) {
    elements_.keep_on_device();
    others_.keep_on_device();
    dirichlet_.keep_on_device();
  }
  PetscCall(PetscLogEventEnd(log_events().coo_reduction, 0, 0, 0, 0));
  PetscCall(make_matrix(template_matrix, extra_rows, extra_cols));
  PetscFunctionReturn(0);
}

PetscErrorCode HessianAssembler::make_matrix(bool template_matrix, const std::vector<PetscInt>& extra_rows,
                                             const std::vector<PetscInt>& extra_cols) {
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
    unique_rows.insert(unique_rows.end(), extra_rows.begin(), extra_rows.end());
    unique_cols.insert(unique_cols.end(), extra_cols.begin(), extra_cols.end());
    PetscCall(MatSetPreallocationCOO(J_, static_cast<PetscCount>(num_unique_), unique_rows.data(), unique_cols.data()));
  } else {
    // A new matrix of the entries; it replaces the template create_matrix() made, or the
    // contents of the matrix in use (whose handle the solvers hold).
    PetscCall(PetscLogEventBegin(log_events().direct_matrix, 0, 0, 0, 0));
    Mat fresh;
    PetscCall(direct_.create(J_, direct_kind_, &elements_.blocks(), extra_rows.data(), extra_cols.data(),
                             extra_rows.size(), &fresh));
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
  if (elements_.chunked()) unique_values_.assign(num_unique_, 0.0);
  PetscFunctionReturn(0);
}

bool HessianAssembler::add_element_chunks(std::size_t t, const double* x) {
  return elements_.add_chunks(static_cast<std::size_t>(element_map_[t]), *terms_[t].pattern, x, unique_values_.data());
}

double* HessianAssembler::values_for(std::size_t t) {
  // A term evaluated away from the matrix writes its block where it runs, and the block crosses
  // once (values_written): device terms into d_values_ (sized whenever there are device terms),
  // host terms into host_block_.
  if (terms_[t].space == MemorySpace::device) return d_values_.data() + term_begin_[t];
  if (device_matrix_) {
    host_block_.resize(term_size_[t]);
    return host_block_.data();
  }
  // values_ starts after the element part when that is summed chunk by chunk.
  return values_.data() + (term_begin_[t] - host_raw_offset());
}

void HessianAssembler::values_written(std::size_t t) {
  const bool on_device = terms_[t].space == MemorySpace::device;
  const std::size_t begin = term_begin_[t], bytes = term_size_[t] * sizeof(double);
  if (on_device == device_matrix_ || bytes == 0) return;
  if (on_device)
    device::copy_to_host(values_.data() + (begin - host_raw_offset()), d_values_.data() + begin, bytes);
  else
    device::copy_to_device(d_values_.data() + begin, host_block_.data(), bytes);
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
  // Per entry: the element part's sum, plus the COO part's sum (entries of their own start from
  // 0), then the Dirichlet elimination; the same order on the host and on the device.
  const std::size_t num_block_entries = elements_.blocks().num_entries();
  if (device_matrix_) {
    d_unique_values_.resize(num_unique_);
    double* unique = d_unique_values_.data();
    elements_.reduce_on_device(d_values_.data(), unique);
    others_.add_on_device(d_values_.data() + num_element_raw_, unique, num_block_entries);
    dirichlet_.apply_on_device(unique);
    return unique;
  }
  unique_values_.resize(num_unique_);
  double* unique = unique_values_.data();
  elements_.reduce(values_.data(), unique);  // nothing when chunked: add_element_chunks summed them
  others_.add(values_.data() + (num_element_raw_ - host_raw_offset()), unique, num_block_entries);
  dirichlet_.apply(unique);
  return unique;
}

}  // namespace dipc
