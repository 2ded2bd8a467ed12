#include "potential/incremental_potential.hpp"

#include <petsc/private/petscimpl.h>  // PetscObjectStateGet: has x changed since the patterns were asked

#include <algorithm>
#include <limits>
#include <tuple>
#include <utility>

#include "logging/log_stages.hpp"

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
}  // namespace

EvaluationTimes operator-(const EvaluationTimes& a, const EvaluationTimes& b) {
  EvaluationTimes d;
  d.energy = a.energy - b.energy, d.gradient = a.gradient - b.gradient, d.hessian = a.hessian - b.hessian;
  d.validity = a.validity - b.validity, d.coo_insert = a.coo_insert - b.coo_insert;
  d.preallocation = a.preallocation - b.preallocation, d.preallocations = a.preallocations - b.preallocations;
  d.remaps = a.remaps - b.remaps;
  d.segment = a.segment - b.segment, d.neighbourhood = a.neighbourhood - b.neighbourhood;
  d.max_step = a.max_step - b.max_step;
  return d;
}

EvaluationTimes& operator+=(EvaluationTimes& s, const EvaluationTimes& a) {
  s.energy += a.energy, s.gradient += a.gradient, s.hessian += a.hessian, s.validity += a.validity;
  s.coo_insert += a.coo_insert, s.preallocation += a.preallocation, s.preallocations += a.preallocations;
  s.remaps += a.remaps;
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
  // Extra nodes are other ranks' nodes (form.hpp): on one rank every node is local, so its
  // forms are not asked, and the segment is not copied to the host for them (in a GPU run,
  // x and p at every Newton iteration, and a pass over the whole contact surface).
  int num_ranks = 1;
  PetscCallMPI(MPI_Comm_size(comm_, &num_ranks));
  any_extra_nodes_ = any_extra_nodes_ && num_ranks > 1;
  // Global dof ids (3 per node) index PETSc's vectors and matrix as PetscInt.
  PetscCheck(3 * static_cast<std::int64_t>(mesh.num_global_nodes) - 1 <= static_cast<std::int64_t>(PETSC_MAX_INT),
             comm_, PETSC_ERR_SUP,
             "%lld nodes need %lld dofs, more than PETSc's %d-bit PetscInt holds: use a PETSc configured with "
             "--with-64-bit-indices, or a smaller mesh",
             static_cast<long long>(mesh.num_global_nodes), 3 * static_cast<long long>(mesh.num_global_nodes),
             static_cast<int>(8 * sizeof(PetscInt)));
  dirichlet_dof_ = std::move(dirichlet_dof);
  num_owned_dofs_ = 3 * mesh.num_owned_nodes;
  // The combined pattern is built by create_matrix(), the first call that needs it (hessian()
  // requires that matrix); building it here too cost a second pass over every COO entry.
  std::vector<HessianAssembler::Term> terms;
  for (const auto& form : forms_) terms.push_back({form.get(), form->memory_space(), form->name()});
  PetscCall(assembler_.setup({comm_, mesh.node_offset, mesh.num_owned_nodes, &local_to_global_, &dirichlet_dof_},
                             std::move(terms)));
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
  PetscFunctionReturn(0);
}

PetscErrorCode IncrementalPotential::rebuild_exchange() {
  PetscFunctionBeginUser;
  local_to_global_ = mesh_->local_to_global;
  for (auto& form : forms_)
    if (const auto* extra = form->extra_nodes())
      local_to_global_.insert(local_to_global_.end(), extra->begin(), extra->end());
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

PetscErrorCode IncrementalPotential::create_matrix(Mat* J) {
  PetscFunctionBeginUser;
  const double start = MPI_Wtime();
  PetscCall(assembler_.create_matrix(J));
  times_.preallocation += MPI_Wtime() - start;
  ++times_.preallocations;
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
  PetscCheck(J == assembler_.matrix(), comm_, PETSC_ERR_ARG_WRONG,
             "hessian() needs the matrix made by create_matrix()");
  PetscCall(gather(x));
  PetscCall(x_views_.begin(x_local_));
  if (any_pattern_change_) {
    bool new_matrix;
    PetscCall(update_patterns(x, &new_matrix));
    if (new_matrix) {
      const double start = MPI_Wtime();
      PetscCall(assembler_.rebuild_pattern());
      times_.preallocation += MPI_Wtime() - start;
      ++times_.preallocations;
    }
  }
  PetscCall(assembler_.begin_values());
  const bool ok = assemble_values(x_views_);
  PetscCall(x_views_.end());
  PetscCheck(ok, PETSC_COMM_SELF, PETSC_ERR_PLIB, "Hessian requested at an inverted state");
  const double insert_start = MPI_Wtime();
  PetscCall(assembler_.insert_values());
  times_.coo_insert += MPI_Wtime() - insert_start;
  PetscFunctionReturn(0);
}

bool IncrementalPotential::assemble_values(LocalViews& x) {
  bool ok = true;
  for (std::size_t f = 0; f < forms_.size(); ++f) {
    if (assembler_.sums_element_chunks(f)) {
      ok = assembler_.add_element_chunks(f, x.in(forms_[f]->memory_space())) && ok;
      continue;
    }
    const MemorySpace space = forms_[f]->memory_space();
    ok = forms_[f]->hessian(x.in(space), assembler_.values_for(f)) && ok;
    assembler_.values_written(f);
  }
  return ok;
}

PetscErrorCode IncrementalPotential::update_patterns(Vec x, bool* new_matrix) {
  PetscFunctionBeginUser;
  // Newton asks at the start of each iteration (refresh_pattern) and again for the Hessian at
  // the same x: the second time the patterns (an O(candidates) pass of the contact form) are
  // those of the first, which left the matrix fitting them.
  PetscObjectState state;
  PetscCall(PetscObjectStateGet(reinterpret_cast<PetscObject>(x), &state));
  *new_matrix = false;
  if (x == patterns_x_ && state == patterns_state_ && assembler_.matrix()) PetscFunctionReturn(0);
  patterns_x_ = x, patterns_state_ = state;
  const double start = MPI_Wtime();
  const long remaps_before = assembler_.remaps();
  const double* xd = uses(MemorySpace::device) ? x_views_.in(MemorySpace::device) : nullptr;
  PetscCall(assembler_.update_patterns(x_views_.in(MemorySpace::host), xd, new_matrix));
  times_.remaps += assembler_.remaps() - remaps_before;
  times_.preallocation += MPI_Wtime() - start;
  PetscFunctionReturn(0);
}

PetscErrorCode IncrementalPotential::refresh_pattern(Vec x, PetscBool* changed, PetscBool* remapped) {
  PetscFunctionBeginUser;
  *changed = PETSC_FALSE;
  *remapped = PETSC_FALSE;
  if (!any_pattern_change_) PetscFunctionReturn(0);  // the matrix made at setup serves the whole run
  PetscCall(gather(x));
  PetscCall(x_views_.begin(x_local_));
  bool new_matrix;
  const long remaps_before = assembler_.remaps();  // the same count on every rank
  PetscCall(update_patterns(x, &new_matrix));
  PetscCall(x_views_.end());
  *changed = new_matrix ? PETSC_TRUE : PETSC_FALSE;
  *remapped = assembler_.remaps() > remaps_before ? PETSC_TRUE : PETSC_FALSE;
  if (new_matrix) assembler_.forget_matrix();  // the caller replaces the matrix: create_matrix() rebuilds the pattern
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

PetscErrorCode IncrementalPotential::min_volume_ratio(Vec x, double* ratio, bool* found) {
  PetscFunctionBeginUser;
  ScopedEvent timer(log_events().validity, &times_.validity);
  PetscCall(gather(x));
  PetscCall(x_views_.begin(x_local_));
  double local = std::numeric_limits<double>::max();
  int any = 0;
  for (auto& form : forms_) {
    double r = 0;
    if (form->min_volume_ratio(x_views_.in(form->memory_space()), &r)) {
      local = std::min(local, r);
      any = 1;
    }
  }
  PetscCall(x_views_.end());
  int any_rank = 0;
  PetscCallMPI(MPI_Allreduce(&any, &any_rank, 1, MPI_INT, MPI_MAX, comm_));
  PetscCallMPI(MPI_Allreduce(&local, ratio, 1, MPI_DOUBLE, MPI_MIN, comm_));
  *found = any_rank != 0;
  PetscFunctionReturn(0);
}

PetscErrorCode IncrementalPotential::prepare_segment(Vec x, Vec p) {
  PetscFunctionBeginUser;
  patterns_x_ = nullptr;  // new candidates: the patterns are asked again
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
    device::axpy_into(seg_w_device_.data(), seg_x_device_.data(), alpha, seg_p_device_.data(), seg_w_device_.size());
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
  patterns_x_ = nullptr;  // forms may adapt (friction's lagged pairs)
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
