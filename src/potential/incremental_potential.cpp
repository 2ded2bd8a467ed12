#include "potential/incremental_potential.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <tuple>
#include <utility>

#include "assembly/cuda/element_kernels.hpp"
#include "assembly/device_matrix.hpp"
#include "logging/log_stages.hpp"
#include "threads/host_threads.hpp"

namespace dipc {

namespace {
// A scope timer that feeds both a PETSc log event (log_stages.hpp) and an EvaluationTimes counter.
class ScopedEvent {
 public:
  ScopedEvent(PetscLogEvent event, double* seconds) : event_(event), seconds_(seconds), start_(MPI_Wtime()) {
    PetscLogEventBegin(event_, 0, 0, 0, 0);
  }
  ~ScopedEvent() {
    PetscLogEventEnd(event_, 0, 0, 0, 0);
    *seconds_ += MPI_Wtime() - start_;
  }

 private:
  PetscLogEvent event_;
  double* seconds_;
  double start_;
};
// -dipc_direct_matrix (default on): matrices of the types DirectMatrix serves are made from the
// entries; off, every matrix goes through PETSc's COO preallocation (for comparison).
PetscErrorCode read_direct_matrix(MPI_Comm comm, bool* direct) {
  PetscFunctionBeginUser;
  PetscBool flag = PETSC_TRUE;
  PetscOptionsBegin(comm, nullptr, "dipc Hessian matrix", "Mat");
  PetscCall(PetscOptionsBool("-dipc_direct_matrix",
                             "Make host AIJ (and device hypre) Hessians from dipc's own pattern instead of PETSc's "
                             "COO preallocation",
                             "DirectMatrix", flag, &flag, nullptr));
  PetscOptionsEnd();
  *direct = flag == PETSC_TRUE;
  PetscFunctionReturn(0);
}
}  // namespace

EvaluationTimes operator-(const EvaluationTimes& a, const EvaluationTimes& b) {
  EvaluationTimes d;
  d.energy = a.energy - b.energy, d.gradient = a.gradient - b.gradient, d.hessian = a.hessian - b.hessian;
  d.validity = a.validity - b.validity, d.coo_insert = a.coo_insert - b.coo_insert;
  d.preallocation = a.preallocation - b.preallocation, d.preallocations = a.preallocations - b.preallocations;
  d.segment = a.segment - b.segment, d.neighbourhood = a.neighbourhood - b.neighbourhood;
  d.max_step = a.max_step - b.max_step;
  return d;
}

EvaluationTimes& operator+=(EvaluationTimes& s, const EvaluationTimes& a) {
  s.energy += a.energy, s.gradient += a.gradient, s.hessian += a.hessian, s.validity += a.validity;
  s.coo_insert += a.coo_insert, s.preallocation += a.preallocation, s.preallocations += a.preallocations;
  s.segment += a.segment, s.neighbourhood += a.neighbourhood, s.max_step += a.max_step;
  return s;
}

IncrementalPotential::~IncrementalPotential() {
  VecDestroy(&x_local_);
  VecDestroy(&g_local_);
  VecDestroy(&p_local_);
  VecDestroy(&dirichlet_global_);
  VecDestroy(&dirichlet_keep_);
}

PetscErrorCode IncrementalPotential::setup(const DistributedMesh& mesh, std::vector<std::unique_ptr<Form>> forms,
                                           std::vector<char> dirichlet_dof, const GhostExchange* nodal) {
  PetscFunctionBeginUser;
  comm_ = mesh.comm;
  mesh_ = &mesh;
  forms_ = std::move(forms);
  for (const auto& form : forms_) {
    (form->memory_space() == MemorySpace::device ? any_device_ : any_host_) = true;
    any_extra_nodes_ = any_extra_nodes_ || form->extra_nodes() != nullptr;
    any_step_limit_ = any_step_limit_ || form->limits_step();
    any_pattern_change_ = any_pattern_change_ || form->pattern_may_change();
  }
  // Global dof ids (3 per node) index PETSc's vectors and matrix as PetscInt.
  PetscCheck(3 * static_cast<std::int64_t>(mesh.num_global_nodes) - 1 <= static_cast<std::int64_t>(PETSC_MAX_INT),
             comm_, PETSC_ERR_SUP,
             "%lld nodes need %lld dofs, more than PETSc's %d-bit PetscInt holds: use a PETSc configured with "
             "--with-64-bit-indices, or a smaller mesh",
             static_cast<long long>(mesh.num_global_nodes), 3 * static_cast<long long>(mesh.num_global_nodes),
             static_cast<int>(8 * sizeof(PetscInt)));
  dirichlet_dof_ = std::move(dirichlet_dof);
  num_owned_dofs_ = 3 * mesh.num_owned_nodes;
  PetscCall(read_direct_matrix(comm_, &direct_matrix_allowed_));
  local_to_global_ = mesh.local_to_global;
  if (nodal && nodal->block_size() == 3)
    PetscCall(exchange_.share(*nodal));
  else
    PetscCall(exchange_.setup(mesh, 3));
  // Prescribed dofs as a distributed field, so that the flags of extra nodes can be gathered.
  PetscCall(exchange_.create_global_vec(&dirichlet_global_));
  PetscScalar* d;
  PetscCall(VecGetArray(dirichlet_global_, &d));
  for (int k = 0; k < num_owned_dofs_; ++k) d[k] = dirichlet_dof_[k] ? 1.0 : 0.0;
  PetscCall(VecRestoreArray(dirichlet_global_, &d));
  // Gradient rows of prescribed dofs are zeroed by a pointwise product, which runs wherever the
  // gradient Vec lives.
  PetscCall(VecDuplicate(dirichlet_global_, &dirichlet_keep_));
  PetscCall(VecSet(dirichlet_keep_, 1.0));
  PetscCall(VecAXPY(dirichlet_keep_, -1.0, dirichlet_global_));
  PetscCall(exchange_.create_local_vec(&x_local_));
  PetscCall(VecDuplicate(x_local_, &g_local_));
  PetscCall(VecDuplicate(x_local_, &p_local_));
  // The combined pattern is built by create_matrix(), the first call that needs it (hessian()
  // requires that matrix); building it here too cost a second pass over every COO entry.
  for (const auto& form : forms_) pattern_versions_.push_back(form->pattern_version());
  PetscFunctionReturn(0);
}

PetscErrorCode IncrementalPotential::rebuild_exchange() {
  PetscFunctionBeginUser;
  local_to_global_ = mesh_->local_to_global;
  for (auto& form : forms_)
    if (const auto* extra = form->extra_nodes()) local_to_global_.insert(local_to_global_.end(), extra->begin(), extra->end());
  PetscCall(exchange_.setup(comm_, mesh_->num_owned_nodes, local_to_global_, mesh_->num_global_nodes, 3));
  PetscCall(VecDestroy(&x_local_));
  PetscCall(VecDestroy(&g_local_));
  PetscCall(VecDestroy(&p_local_));
  PetscCall(exchange_.create_local_vec(&x_local_));
  PetscCall(VecDuplicate(x_local_, &g_local_));
  PetscCall(VecDuplicate(x_local_, &p_local_));
  PetscCall(exchange_.to_local(dirichlet_global_, g_local_));
  const PetscScalar* d;
  PetscCall(VecGetArrayRead(g_local_, &d));
  dirichlet_dof_.assign(3 * local_to_global_.size(), 0);
  for (std::size_t k = 0; k < dirichlet_dof_.size(); ++k) dirichlet_dof_[k] = d[k] > 0.5;
  PetscCall(VecRestoreArrayRead(g_local_, &d));
  PetscFunctionReturn(0);
}

bool IncrementalPotential::pattern_changed() const {
  for (std::size_t f = 0; f < forms_.size(); ++f)
    if (forms_[f]->pattern_version() != pattern_versions_[f]) return true;
  return false;
}

PetscErrorCode IncrementalPotential::build_element_blocks() {
  PetscFunctionBeginUser;
  // The element forms' values come first in the raw array, so that their offsets (and the map's)
  // stay put when the other forms' patterns change; their patterns never do.
  std::vector<NodeBlockReduction::Input> inputs;
  form_begin_.assign(forms_.size(), 0);
  form_size_.assign(forms_.size(), 0);
  element_map_.assign(forms_.size(), -1);
  bool all_host = true;
  std::size_t raw = 0;
  for (std::size_t f = 0; f < forms_.size(); ++f) {
    ElementPattern pattern;
    if (!forms_[f]->element_pattern(&pattern)) continue;
    PetscCheck(!forms_[f]->pattern_may_change(), PETSC_COMM_SELF, PETSC_ERR_PLIB,
               "form %s gives node blocks but says its pattern may change", forms_[f]->name().c_str());
    element_map_[f] = static_cast<int>(inputs.size());
    all_host = all_host && forms_[f]->memory_space() == MemorySpace::host;
    form_begin_[f] = raw;
    form_size_[f] = static_cast<std::size_t>(element_values(pattern.layout)) * static_cast<std::size_t>(pattern.num_elements);
    inputs.push_back({pattern, raw});
    raw += form_size_[f];
  }
  PetscCheck(inputs.size() <= static_cast<std::size_t>(device::kMaxElementBlockMaps), PETSC_COMM_SELF, PETSC_ERR_SUP,
             "%zu element forms; the node-block reduction takes at most %d", inputs.size(),
             device::kMaxElementBlockMaps);
  num_element_raw_ = raw;
  const std::int64_t owned_begin = mesh_->node_offset, owned_end = mesh_->node_offset + mesh_->num_owned_nodes;
  try {
    if (device_matrix_ && !inputs.empty()) {
      // The device sums the values through the maps: they are built there (a radix sort of the
      // element node pairs) and stay there; the host gets the pattern.
      device::NodeBlocks on_device;
      blocks_ = NodeBlockReduction::build_on_device(inputs, owned_begin, owned_end, &on_device);
      d_block_mask_.resize(on_device.mask.size());
      device::copy_on_device(d_block_mask_.data(), on_device.mask.data(), on_device.mask.size() * sizeof(std::uint16_t));
      d_block_start_.resize(on_device.start.size());
      device::copy_on_device(d_block_start_.data(), on_device.start.data(),
                             on_device.start.size() * sizeof(std::uint64_t));
      for (std::size_t m = 0; m < inputs.size(); ++m) {
        d_block_offsets_.push_back(std::move(on_device.offsets[m]));
        d_block_sources_.push_back(std::move(on_device.sources[m]));
      }
    } else {
      blocks_ = NodeBlockReduction::build(inputs, owned_begin, owned_end);
    }
    // A host matrix of host element forms sums their values element chunk by chunk (no array
    // of all their raw values); the device sums them all at once, through the sources.
    chunked_ = !inputs.empty() && all_host && !device_matrix_;
    if (chunked_) blocks_.index_elements();
  } catch (const std::length_error& e) {
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_SUP, "%s", e.what());
  }
  PetscFunctionReturn(0);
}

PetscErrorCode IncrementalPotential::rebuild_pattern(bool template_matrix) {
  PetscFunctionBeginUser;
  const double start = MPI_Wtime();
  PetscCall(PetscLogEventBegin(log_events().coo_reduction, 0, 0, 0, 0));
  device_matrix_ = any_device_ && matrix_on_device(J_);
  // Host AIJ, and hypre on the device when the values are summed there, are made from the
  // entries directly (direct_matrix.hpp); other types and -dipc_direct_matrix 0 take PETSc's
  // COO path.
  direct_kind_ = direct_matrix_allowed_ ? DirectMatrix::kind_of(J_) : DirectMatrix::Kind::coo;
  if (direct_kind_ == DirectMatrix::Kind::device_hypre && !device_matrix_) direct_kind_ = DirectMatrix::Kind::coo;
  if (!blocks_built_) {
    PetscCall(PetscLogEventBegin(log_events().node_blocks, 0, 0, 0, 0));
    PetscCall(build_element_blocks());
    PetscCall(PetscLogEventEnd(log_events().node_blocks, 0, 0, 0, 0));
    blocks_built_ = true;
  }
  // The other forms' raw COO lists (contact, friction, the lumped mass: small, or changing with
  // the active set) after the element forms' values, then the Dirichlet diagonal.
  std::vector<PetscInt> rows, cols;
  {
    std::vector<std::vector<PetscInt>> form_rows(forms_.size()), form_cols(forms_.size());
    std::size_t total = 0;
    for (std::size_t f = 0; f < forms_.size(); ++f)
      if (element_map_[f] < 0) {
        forms_[f]->coo_pattern(&form_rows[f], &form_cols[f]);
        total += form_rows[f].size();
      }
    for (int k = 0; k < num_owned_dofs_; ++k) total += dirichlet_dof_[k] ? 1 : 0;
    rows.reserve(total), cols.reserve(total);
    pattern_versions_.clear();
    for (std::size_t f = 0; f < forms_.size(); ++f) {
      pattern_versions_.push_back(forms_[f]->pattern_version());
      if (element_map_[f] >= 0) continue;
      form_begin_[f] = num_element_raw_ + rows.size();
      form_size_[f] = form_rows[f].size();
      rows.insert(rows.end(), form_rows[f].begin(), form_rows[f].end());
      cols.insert(cols.end(), form_cols[f].begin(), form_cols[f].end());
    }
  }
  // Diagonal entries of the owned prescribed dofs: in the pattern, so that kinematic nodes
  // (no element of theirs is assembled) get one; their value is set by the elimination below.
  dirichlet_raw_begin_ = num_element_raw_ + rows.size();
  for (int k = 0; k < num_owned_dofs_; ++k)
    if (dirichlet_dof_[k]) {
      const PetscInt dof = static_cast<PetscInt>(3 * mesh_->node_offset + k);
      rows.push_back(dof);
      cols.push_back(dof);
    }
  num_raw_entries_ = num_element_raw_ + rows.size();
  const PetscInt owned_begin = static_cast<PetscInt>(3 * mesh_->node_offset);
  try {
    reduction_ = CooReduction::build(rows.data(), cols.data(), rows.size(), owned_begin, owned_begin + num_owned_dofs_);
  } catch (const std::length_error& e) {
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_SUP, "%s", e.what());
  }
  std::vector<PetscInt>().swap(rows);
  std::vector<PetscInt>().swap(cols);

  // The matrix's entries: the element blocks', then those of the other forms that no block
  // holds (extra_rows/extra_cols). scalar_target_[v] is where the other forms' unique entry v is
  // added.
  num_block_entries_ = blocks_.num_entries();
  std::vector<PetscInt> extra_rows, extra_cols;
  // In chunks on the host threads (the lumped mass gives 3 entries per node), each with its own
  // row hint; a chunk's extra entries are numbered after the lower chunks', in row order.
  const std::size_t num_scalar = reduction_.num_unique();
  scalar_target_.resize(num_scalar);
  constexpr std::size_t kInNoBlock = std::numeric_limits<std::size_t>::max();
  std::vector<std::size_t> chunk_extras(static_cast<std::size_t>(host_threads()), 0);
  const int chunks = parallel_chunks(num_scalar, [&](int c, std::size_t v0, std::size_t v1) {
    std::size_t row_hint = 0, extras = 0;  // the unique entries ascend by row
    for (std::size_t v = v0; v < v1; ++v) {
      const std::int64_t k = blocks_.find(reduction_.rows[v], reduction_.cols[v], &row_hint);
      scalar_target_[v] = k >= 0 ? static_cast<std::size_t>(k) : kInNoBlock;
      extras += k < 0;
    }
    chunk_extras[static_cast<std::size_t>(c)] = extras;
  });
  const std::size_t num_extras = chunk_starts(chunk_extras, chunks)[0];
  extra_rows.resize(num_extras), extra_cols.resize(num_extras);
  parallel_chunks(num_scalar, [&](int c, std::size_t v0, std::size_t v1) {
    std::size_t next = chunk_extras[static_cast<std::size_t>(c)];
    for (std::size_t v = v0; v < v1; ++v)
      if (scalar_target_[v] == kInNoBlock) {
        scalar_target_[v] = num_block_entries_ + next;
        extra_rows[next] = reduction_.rows[v];
        extra_cols[next] = reduction_.cols[v];
        ++next;
      }
  });
  std::vector<PetscInt>().swap(reduction_.rows);
  std::vector<PetscInt>().swap(reduction_.cols);
  num_unique_ = num_block_entries_ + extra_rows.size();
  // PETSc's AIJ matrices count a rank's nonzeros in PetscInt (row offsets).
  PetscCheck(num_unique_ <= static_cast<std::size_t>(PETSC_MAX_INT), PETSC_COMM_SELF, PETSC_ERR_SUP,
             "this rank's Hessian has %zu nonzeros, more than PETSc's %d-bit PetscInt holds: run on more ranks, or "
             "use a PETSc configured with --with-64-bit-indices",
             num_unique_, static_cast<int>(8 * sizeof(PetscInt)));
  find_dirichlet_entries(extra_rows, extra_cols);

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
  // The maps go to the device where hessian() sums there (device forms and a device matrix),
  // and then leave the host; the blocks' layout stays for the next pattern change.
  if (device_matrix_) {
    if (d_block_sources_.empty()) {
      d_block_mask_.upload(blocks_.block_mask);
      d_block_start_.upload(blocks_.block_start);
      for (auto& form : blocks_.forms) {
        d_block_offsets_.emplace_back("node-block offsets");
        d_block_offsets_.back().upload(form.offsets);
        d_block_sources_.emplace_back("node-block sources");
        d_block_sources_.back().upload(form.sources);
        LargePageVector<std::uint32_t>().swap(form.offsets);
        LargePageVector<std::uint32_t>().swap(form.sources);
      }
    }
    d_reduction_offsets_.upload(reduction_.offsets);
    d_reduction_sources_.upload(reduction_.sources);
    std::vector<CooReduction::Index>().swap(reduction_.offsets);
    std::vector<CooReduction::Index>().swap(reduction_.sources);
    d_scalar_target_.upload(scalar_target_);
    d_zero_entries_.upload(zero_entries_);
    d_one_entries_.upload(one_entries_);
  }
  PetscCall(PetscLogEventEnd(log_events().coo_reduction, 0, 0, 0, 0));
  if (direct_kind_ == DirectMatrix::Kind::coo) {
    // PETSc's COO path takes every entry as a (row, col) pair; it may reorder the index arrays it
    // is given and keeps its own copy.
    std::vector<PetscInt> unique_rows, unique_cols;
    try {
      blocks_.entries(&unique_rows, &unique_cols);
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
    PetscCall(direct_.create(J_, direct_kind_, &blocks_, extra_rows.data(), extra_cols.data(), extra_rows.size(), &fresh));
    if (template_matrix) {
      PetscCall(MatDestroy(&J_));
      J_ = fresh;
    } else {
      PetscCall(MatHeaderReplace(J_, &fresh));
    }
    PetscCall(PetscLogEventEnd(log_events().direct_matrix, 0, 0, 0, 0));
  }
  times_.preallocation += MPI_Wtime() - start;
  ++times_.preallocations;
  PetscFunctionReturn(0);
}

void IncrementalPotential::find_dirichlet_entries(const std::vector<PetscInt>& extra_rows,
                                                  const std::vector<PetscInt>& extra_cols) {
  // Zero in a prescribed row or column, one on an owned prescribed diagonal (a ghost row's
  // diagonal is its owner's). Prescribed global dofs as a bitmap over their id range; a block
  // whose two nodes have none is passed over whole.
  zero_entries_.clear();
  one_entries_.clear();
  PetscInt lo = std::numeric_limits<PetscInt>::max(), hi = -1;
  for (std::size_t n = 0; n < local_to_global_.size(); ++n)
    for (int c = 0; c < 3; ++c)
      if (dirichlet_dof_[3 * n + c]) {
        const PetscInt dof = static_cast<PetscInt>(3 * local_to_global_[n] + c);
        lo = std::min(lo, dof), hi = std::max(hi, dof);
      }
  if (hi < lo) return;
  std::vector<bool> prescribed(static_cast<std::size_t>(hi - lo + 1), false);
  for (std::size_t n = 0; n < local_to_global_.size(); ++n)
    for (int c = 0; c < 3; ++c)
      if (dirichlet_dof_[3 * n + c]) prescribed[static_cast<PetscInt>(3 * local_to_global_[n] + c) - lo] = true;
  const auto is_prescribed = [&](std::int64_t dof) { return dof >= lo && dof <= hi && prescribed[dof - lo]; };
  const auto node_prescribed = [&](std::int64_t node) {
    return is_prescribed(3 * node) || is_prescribed(3 * node + 1) || is_prescribed(3 * node + 2);
  };
  const PetscInt owned_begin = static_cast<PetscInt>(3 * mesh_->node_offset);
  const auto classify = [&](std::size_t u, std::int64_t r, std::int64_t c) {
    if (!is_prescribed(r) && !is_prescribed(c)) return;
    const bool owned_diagonal = r == c && r >= owned_begin && r < owned_begin + num_owned_dofs_;
    (owned_diagonal ? one_entries_ : zero_entries_).push_back(u);
  };
  for (std::size_t s = 0; s < blocks_.row_nodes.size(); ++s) {
    const std::int64_t row_node = blocks_.row_nodes[s];
    const bool row_any = node_prescribed(row_node);
    for (std::size_t k = blocks_.row_start[s]; k < blocks_.row_start[s + 1]; ++k) {
      if (!row_any && !node_prescribed(blocks_.block_col[k])) continue;
      blocks_.for_each_entry(row_node, k, classify);
    }
  }
  for (std::size_t v = 0; v < extra_rows.size(); ++v) classify(num_block_entries_ + v, extra_rows[v], extra_cols[v]);
}

PetscErrorCode IncrementalPotential::create_matrix(Mat* J) {
  PetscFunctionBeginUser;
  const double start = MPI_Wtime();
  const double before = times_.preallocation;
  PetscCall(MatCreate(comm_, J));
  PetscCall(MatSetSizes(*J, num_owned_dofs_, num_owned_dofs_, PETSC_DETERMINE, PETSC_DETERMINE));
  PetscCall(MatSetBlockSize(*J, 3));
  PetscCall(MatSetType(*J, MATAIJ));
  PetscCall(MatSetFromOptions(*J));
  J_ = *J;
  PetscCall(rebuild_pattern(true));
  *J = J_;  // a direct matrix replaced the template
  PetscCall(MatSetOption(*J, MAT_SPD, PETSC_TRUE));
  times_.preallocation = before + (MPI_Wtime() - start);
  PetscFunctionReturn(0);
}

PetscErrorCode IncrementalPotential::gather(Vec x) {
  PetscFunctionBeginUser;
  PetscCall(exchange_.to_local(x, x_local_));
  PetscFunctionReturn(0);
}

PetscErrorCode IncrementalPotential::objective(Vec x, PetscReal* energy) {
  PetscFunctionBeginUser;
  ScopedEvent timer(log_events().energy, &times_.energy);
  std::vector<double> values;
  PetscCall(form_values(x, &values));
  double sum = 0;
  for (double v : values) sum += v;
  *energy = sum;
  PetscFunctionReturn(0);
}

PetscErrorCode IncrementalPotential::form_values(Vec x, std::vector<double>* values) {
  PetscFunctionBeginUser;
  PetscCall(gather(x));
  PetscCall(x_views_.begin(x_local_));
  std::vector<double> local(forms_.size(), 0.0);
  const double* xh = uses(MemorySpace::host) ? x_views_.in(MemorySpace::host) : nullptr;
  const double* xd = uses(MemorySpace::device) ? x_views_.in(MemorySpace::device) : nullptr;
  const bool ok = local_values(xh, xd, local.data());
  PetscCall(x_views_.end());
  PetscCall(reduce_values(local, ok, values));
  PetscFunctionReturn(0);
}

PetscErrorCode IncrementalPotential::reduce_values(const std::vector<double>& local, bool ok,
                                                   std::vector<double>* values) {
  PetscFunctionBeginUser;
  const std::size_t nf = local.size();
  std::vector<double> send(local), total(nf + 1);
  send.push_back(ok ? 0.0 : 1.0);
  PetscCallMPI(MPI_Allreduce(send.data(), total.data(), static_cast<int>(nf + 1), MPI_DOUBLE, MPI_SUM, comm_));
  values->assign(total.begin(), total.begin() + nf);
  if (total[nf] > 0)
    for (double& v : *values) v = PETSC_INFINITY;
  PetscFunctionReturn(0);
}

PetscErrorCode IncrementalPotential::all_ranks(bool ok, PetscBool* all) {
  PetscFunctionBeginUser;
  int mine = ok ? 1 : 0, every = 0;
  PetscCallMPI(MPI_Allreduce(&mine, &every, 1, MPI_INT, MPI_MIN, comm_));
  *all = every ? PETSC_TRUE : PETSC_FALSE;
  PetscFunctionReturn(0);
}

PetscErrorCode IncrementalPotential::partial_gradient(Vec x, Vec g, const std::function<bool(const Form&)>& include,
                                                     bool keep_prescribed) {
  PetscFunctionBeginUser;
  ScopedEvent timer(log_events().gradient, &times_.gradient);
  PetscCall(gather(x));
  PetscCall(VecZeroEntries(g_local_));
  PetscCall(x_views_.begin(x_local_));
  PetscScalar* gl;
  PetscMemType g_type;
  PetscCall(VecGetArrayAndMemType(g_local_, &gl, &g_type));
  const MemorySpace g_space = PetscMemTypeHost(g_type) ? MemorySpace::host : MemorySpace::device;
  const std::size_t n = x_views_.size();
  // Forms in the other space than the gradient Vec add into a zeroed scratch array there,
  // which is then added into the Vec once.
  double* g_in[2] = {nullptr, nullptr};  // indexed by MemorySpace
  bool other_used = false;
  for (MemorySpace space : {MemorySpace::host, MemorySpace::device}) {
    if (!uses(space)) continue;
    if (space == g_space) {
      g_in[static_cast<int>(space)] = gl;
    } else if (space == MemorySpace::host) {
      g_host_.assign(n, 0.0);
      g_in[0] = g_host_.data();
      other_used = true;
    } else {
      g_device_.resize(n);
      g_device_.set_zero();
      g_in[1] = g_device_.data();
      other_used = true;
    }
  }
  bool ok = true;
  for (auto& form : forms_)
    if (!include || include(*form)) {
      const MemorySpace space = form->memory_space();
      ok = form->gradient(x_views_.in(space), g_in[static_cast<int>(space)]) && ok;
    }
  if (other_used) {
    if (g_space == MemorySpace::host) {
      g_host_.resize(n);
      g_device_.download(g_host_.data());
      for (std::size_t k = 0; k < n; ++k) gl[k] += g_host_[k];
    } else {
      g_device_.upload(g_host_);
      device::add_scaled(gl, 1.0, g_device_.data(), n);
    }
  }
  PetscCall(VecRestoreArrayAndMemType(g_local_, &gl));
  PetscCall(x_views_.end());
  PetscCheck(ok, PETSC_COMM_SELF, PETSC_ERR_PLIB, "gradient requested at an inverted state");
  PetscCall(VecZeroEntries(g));
  PetscCall(exchange_.add_to_global(g_local_, g));
  if (!keep_prescribed) PetscCall(VecPointwiseMult(g, g, dirichlet_keep_));
  PetscFunctionReturn(0);
}

PetscErrorCode IncrementalPotential::gradient(Vec x, Vec g) {
  PetscFunctionBeginUser;
  PetscCall(partial_gradient(x, g, {}));  // timed there
  PetscFunctionReturn(0);
}

PetscErrorCode IncrementalPotential::hessian(Vec x, Mat J) {
  PetscFunctionBeginUser;
  // A pattern rebuilt here is preallocation time, not Hessian time (the timers are disjoint).
  const double preallocation_before = times_.preallocation;
  {
    ScopedEvent timer(log_events().hessian, &times_.hessian);
    PetscCall(assemble_hessian(x, J));
  }
  times_.hessian -= times_.preallocation - preallocation_before;
  PetscFunctionReturn(0);
}

PetscErrorCode IncrementalPotential::assemble_hessian(Vec x, Mat J) {
  PetscFunctionBeginUser;
  PetscCheck(J == J_, comm_, PETSC_ERR_ARG_WRONG, "hessian() needs the matrix made by create_matrix()");
  PetscCall(gather(x));
  PetscCall(x_views_.begin(x_local_));
  if (any_pattern_change_) {
    for (auto& form : forms_) form->update_pattern(x_views_.in(MemorySpace::host));
    int changed = pattern_changed() ? 1 : 0, any = 0;
    PetscCallMPI(MPI_Allreduce(&changed, &any, 1, MPI_INT, MPI_MAX, comm_));
    if (any) PetscCall(rebuild_pattern(false));
  }
  // Values go to the device only where both the matrix and some forms are there.
  const bool on_device = matrix_on_device(J) && any_device_;
  PetscCheck(on_device == device_matrix_, PETSC_COMM_SELF, PETSC_ERR_PLIB,
             "Hessian requested into a matrix in another memory space than the pattern's");
  const bool ok = assemble_values(x_views_, on_device);
  PetscCall(x_views_.end());
  PetscCheck(ok, PETSC_COMM_SELF, PETSC_ERR_PLIB, "Hessian requested at an inverted state");
  const double insert_start = MPI_Wtime();
  double* const unique = sum_values(on_device);
  if (direct_kind_ == DirectMatrix::Kind::coo)
    PetscCall(MatSetValuesCOO(J, unique, INSERT_VALUES));
  else
    PetscCall(direct_.set_values(J, unique));
  times_.coo_insert += MPI_Wtime() - insert_start;
  PetscFunctionReturn(0);
}

bool IncrementalPotential::assemble_values(LocalViews& x, bool on_device) {
  const MemorySpace target = on_device ? MemorySpace::device : MemorySpace::host;
  // values_ starts after the element forms' values when those are summed chunk by chunk.
  const std::size_t target_offset = on_device ? 0 : host_raw_offset();
  double* const matrix_values = on_device ? d_values_.data() : values_.data();
  if (chunked_) unique_values_.assign(num_unique_, 0.0);
  bool ok = true;
  for (std::size_t f = 0; f < forms_.size(); ++f) {
    if (chunked_ && element_map_[f] >= 0) {
      ok = add_element_chunks(f, x.in(MemorySpace::host)) && ok;
      continue;
    }
    const MemorySpace space = forms_[f]->memory_space();
    const std::size_t begin = form_begin_[f], count = form_size_[f];
    // A form evaluated away from the matrix writes its block where it runs, and the block
    // crosses once: device forms into d_values_ (sized whenever there are device forms), host
    // forms into host_block_.
    double* own = matrix_values + (begin - target_offset);
    if (space != target) {
      if (space == MemorySpace::device) {
        own = d_values_.data() + begin;
      } else {
        host_block_.resize(count);
        own = host_block_.data();
      }
    }
    ok = forms_[f]->hessian(x.in(space), own) && ok;
    if (space != target) copy_between(target, matrix_values + (begin - target_offset), space, own, count);
  }
  return ok;
}

bool IncrementalPotential::add_element_chunks(std::size_t f, const double* x) {
  // Small enough to stay in cache (9.4 MB of elastic values), large enough that the calls cost
  // nothing.
  constexpr int kChunk = 2048;
  ElementPattern pattern;
  forms_[f]->element_pattern(&pattern);
  const std::size_t m = static_cast<std::size_t>(element_map_[f]);
  chunk_values_.resize(static_cast<std::size_t>(kChunk) * element_values(pattern.layout));
  bool ok = true;
  for (int first = 0; first < pattern.num_elements; first += kChunk) {
    const int count = std::min(kChunk, pattern.num_elements - first);
    ok = forms_[f]->element_hessian(x, first, count, chunk_values_.data()) && ok;
    blocks_.add_elements(m, first, count, chunk_values_.data(), unique_values_.data());
  }
  return ok;
}

double* IncrementalPotential::sum_values(bool on_device) {
  // Per entry: the element forms' sum, plus the other forms' sum (entries of their own start
  // from 0), then the Dirichlet elimination; the same order on the host and on the device.
  const std::size_t num_scalar = scalar_target_.size();
  if (on_device) {
    d_unique_values_.resize(num_unique_);
    double* unique = d_unique_values_.data();
    std::vector<device::ElementBlockMap> maps;
    for (std::size_t m = 0; m < blocks_.forms.size(); ++m)
      maps.push_back({blocks_.forms[m].layout, blocks_.forms[m].raw_begin, d_block_offsets_[m].data(),
                      d_block_sources_[m].data()});
    device::reduce_element_blocks(d_values_.data(), blocks_.num_blocks(), d_block_mask_.data(), d_block_start_.data(),
                                  maps.data(), static_cast<int>(maps.size()), unique);
    d_scalar_sums_.resize(num_scalar);
    device::reduce_coo(d_values_.data() + num_element_raw_, d_reduction_offsets_.data(), d_reduction_sources_.data(),
                       num_scalar, d_scalar_sums_.data());
    device::add_at(unique, d_scalar_target_.data(), d_scalar_sums_.data(), num_scalar, num_block_entries_);
    device::eliminate(unique, d_zero_entries_.data(), zero_entries_.size(), d_one_entries_.data(), one_entries_.size());
    return unique;
  }
  unique_values_.resize(num_unique_);
  double* unique = unique_values_.data();
  if (!chunked_) blocks_.reduce(values_.data(), unique);  // else summed by assemble_values
  scalar_sums_.resize(num_scalar);
  reduction_.reduce(values_.data() + (num_element_raw_ - host_raw_offset()), scalar_sums_.data());
  for (std::size_t v = 0; v < num_scalar; ++v) {
    const std::size_t u = scalar_target_[v];
    unique[u] = (u < num_block_entries_ ? unique[u] : 0.0) + scalar_sums_[v];
  }
  for (std::size_t u : zero_entries_) unique[u] = 0;
  for (std::size_t u : one_entries_) unique[u] = 1;
  return unique;
}

PetscErrorCode IncrementalPotential::refresh_pattern(Vec x, PetscBool* changed) {
  PetscFunctionBeginUser;
  *changed = PETSC_FALSE;
  if (!any_pattern_change_) PetscFunctionReturn(0);  // the matrix made at setup serves the whole run
  PetscCall(gather(x));
  PetscCall(x_views_.begin(x_local_));
  for (auto& form : forms_) form->update_pattern(x_views_.in(MemorySpace::host));
  PetscCall(x_views_.end());
  int local = pattern_changed() ? 1 : 0, any = 0;
  PetscCallMPI(MPI_Allreduce(&local, &any, 1, MPI_INT, MPI_MAX, comm_));
  *changed = any ? PETSC_TRUE : PETSC_FALSE;
  if (any) J_ = nullptr;  // the caller replaces the matrix: create_matrix() rebuilds the pattern
  PetscFunctionReturn(0);
}

PetscErrorCode IncrementalPotential::is_valid(Vec x, PetscBool* valid) {
  PetscFunctionBeginUser;
  ScopedEvent timer(log_events().validity, &times_.validity);
  PetscCall(gather(x));
  PetscCall(x_views_.begin(x_local_));
  const double* xh = uses(MemorySpace::host) ? x_views_.in(MemorySpace::host) : nullptr;
  const double* xd = uses(MemorySpace::device) ? x_views_.in(MemorySpace::device) : nullptr;
  const bool ok = local_valid(xh, xd);
  PetscCall(x_views_.end());
  PetscCall(all_ranks(ok, valid));
  PetscFunctionReturn(0);
}

PetscErrorCode IncrementalPotential::prepare_segment(Vec x, Vec p) {
  PetscFunctionBeginUser;
  // Timed as `segment` (what every line search needs) apart from the forms' own work on the
  // segment, timed as `neighbourhood`.
  double start = MPI_Wtime();
  // Forms may ask for more nodes once they see the segment; then everything is gathered again
  // over the extended node list. Every rank takes part in the rebuild if any rank needs it.
  PetscCall(gather(x));
  PetscCall(exchange_.to_local(p, p_local_));
  times_.segment += MPI_Wtime() - start;
  start = MPI_Wtime();
  int changed = 0;
  if (any_extra_nodes_) {
    const PetscScalar *xl, *pl;
    PetscCall(VecGetArrayRead(x_local_, &xl));
    PetscCall(VecGetArrayRead(p_local_, &pl));
    for (auto& form : forms_) changed = form->update_extra_nodes(xl, pl) || changed;
    PetscCall(VecRestoreArrayRead(p_local_, &pl));
    PetscCall(VecRestoreArrayRead(x_local_, &xl));
  }
  int any = 0;
  if (any_extra_nodes_) PetscCallMPI(MPI_Allreduce(&changed, &any, 1, MPI_INT, MPI_MAX, comm_));
  if (any) {
    PetscCall(rebuild_exchange());
    PetscCall(gather(x));
    PetscCall(exchange_.to_local(p, p_local_));
  }
  times_.neighbourhood += MPI_Wtime() - start;
  start = MPI_Wtime();
  // Keep the segment in every space the forms use: trial states are built from these copies,
  // and each form prepares the segment on the copies in its own space.
  PetscInt n;
  PetscCall(VecGetLocalSize(x_local_, &n));
  for (auto [vec, host, dev] : {std::make_tuple(x_local_, &seg_x_host_, &seg_x_device_),
                                std::make_tuple(p_local_, &seg_p_host_, &seg_p_device_)}) {
    LocalViews views;
    PetscCall(views.begin(vec));
    if (uses(MemorySpace::host)) host->assign(views.in(MemorySpace::host), views.in(MemorySpace::host) + n);
    if (uses(MemorySpace::device)) {
      dev->resize(static_cast<std::size_t>(n));
      copy_between(MemorySpace::device, dev->data(), MemorySpace::device, views.in(MemorySpace::device),
                   static_cast<std::size_t>(n));
    }
    PetscCall(views.end());
  }
  seg_w_host_.resize(uses(MemorySpace::host) ? static_cast<std::size_t>(n) : 0);
  if (uses(MemorySpace::device)) seg_w_device_.resize(static_cast<std::size_t>(n));
  times_.segment += MPI_Wtime() - start;
  start = MPI_Wtime();
  for (auto& form : forms_) {
    if (form->memory_space() == MemorySpace::device)
      form->prepare_segment(seg_x_device_.data(), seg_p_device_.data());
    else
      form->prepare_segment(seg_x_host_.data(), seg_p_host_.data());
  }
  times_.neighbourhood += MPI_Wtime() - start;
  PetscFunctionReturn(0);
}

PetscErrorCode IncrementalPotential::prepare_point(Vec x) {
  PetscFunctionBeginUser;
  Vec zero;
  PetscCall(VecDuplicate(x, &zero));
  PetscCall(VecZeroEntries(zero));
  PetscCall(prepare_segment(x, zero));
  PetscCall(VecDestroy(&zero));
  PetscFunctionReturn(0);
}

PetscErrorCode IncrementalPotential::max_step(Vec x, Vec p, PetscReal* alpha) {
  PetscFunctionBeginUser;
  PetscCall(prepare_segment(x, p));
  if (!any_step_limit_) {  // nothing bounds the step: no CCD, no reduction
    *alpha = 1.0;
    PetscFunctionReturn(0);
  }
  const double start = MPI_Wtime();
  double a = 1.0;
  for (auto& form : forms_) {
    const bool dev = form->memory_space() == MemorySpace::device;
    a = std::min(a, dev ? form->max_step(seg_x_device_.data(), seg_p_device_.data())
                        : form->max_step(seg_x_host_.data(), seg_p_host_.data()));
  }
  PetscCallMPI(MPI_Allreduce(&a, alpha, 1, MPI_DOUBLE, MPI_MIN, comm_));
  times_.max_step += MPI_Wtime() - start;
  PetscFunctionReturn(0);
}

bool IncrementalPotential::local_values(const double* x_host, const double* x_device, double* values) {
  bool ok = true;
  for (std::size_t f = 0; f < forms_.size(); ++f)
    ok = forms_[f]->value(forms_[f]->memory_space() == MemorySpace::device ? x_device : x_host, &values[f]) && ok;
  return ok;
}

bool IncrementalPotential::local_valid(const double* x_host, const double* x_device) {
  for (auto& form : forms_)
    if (!form->is_valid(form->memory_space() == MemorySpace::device ? x_device : x_host)) return false;
  return true;
}

void IncrementalPotential::segment_point(PetscReal alpha) {
  // Rounded as VecWAXPY rounds w = αp + x: one product, one sum, no fused multiply-add.
  for (std::size_t k = 0; k < seg_w_host_.size(); ++k) seg_w_host_[k] = alpha * seg_p_host_[k] + seg_x_host_[k];
  if (uses(MemorySpace::device))
    device::axpy_into(seg_w_device_.data(), seg_x_device_.data(), alpha, seg_p_device_.data(),
                      seg_w_device_.size());
}

PetscErrorCode IncrementalPotential::segment_objective(PetscReal alpha, PetscReal* energy) {
  PetscFunctionBeginUser;
  ScopedEvent timer(log_events().energy, &times_.energy);
  segment_point(alpha);
  std::vector<double> local(forms_.size(), 0.0), values;
  const bool ok = local_values(seg_w_host_.data(), seg_w_device_.data(), local.data());
  PetscCall(reduce_values(local, ok, &values));
  double sum = 0;
  for (double v : values) sum += v;
  *energy = sum;
  PetscFunctionReturn(0);
}

PetscErrorCode IncrementalPotential::segment_is_valid(PetscReal alpha, PetscBool* valid) {
  PetscFunctionBeginUser;
  ScopedEvent timer(log_events().validity, &times_.validity);
  segment_point(alpha);
  PetscCall(all_ranks(local_valid(seg_w_host_.data(), seg_w_device_.data()), valid));
  PetscFunctionReturn(0);
}

PetscErrorCode IncrementalPotential::with_local(Vec x, const std::function<void(const double*, std::size_t)>& f) {
  PetscFunctionBeginUser;
  PetscCall(gather(x));
  const PetscScalar* xl;
  PetscInt n;
  PetscCall(VecGetLocalSize(x_local_, &n));
  PetscCall(VecGetArrayRead(x_local_, &xl));
  f(xl, static_cast<std::size_t>(n));
  PetscCall(VecRestoreArrayRead(x_local_, &xl));
  PetscFunctionReturn(0);
}

PetscErrorCode IncrementalPotential::begin_step(Vec x_hat) {
  PetscFunctionBeginUser;
  PetscCall(gather(x_hat));
  const PetscScalar* xl;
  PetscCall(VecGetArrayRead(x_local_, &xl));
  for (auto& form : forms_) form->begin_step(xl);
  PetscCall(VecRestoreArrayRead(x_local_, &xl));
  PetscFunctionReturn(0);
}

PetscErrorCode IncrementalPotential::begin_iteration(Vec x, PetscBool* changed) {
  PetscFunctionBeginUser;
  PetscCall(gather(x));
  const PetscScalar* xl;
  PetscCall(VecGetArrayRead(x_local_, &xl));
  int local = 0, any = 0;
  for (auto& form : forms_) local = form->begin_iteration(xl) || local;
  PetscCall(VecRestoreArrayRead(x_local_, &xl));
  PetscCallMPI(MPI_Allreduce(&local, &any, 1, MPI_INT, MPI_MAX, comm_));
  *changed = any ? PETSC_TRUE : PETSC_FALSE;
  PetscFunctionReturn(0);
}

}  // namespace dipc
