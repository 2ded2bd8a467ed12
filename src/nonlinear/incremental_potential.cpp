#include "nonlinear/incremental_potential.hpp"

#include <algorithm>
#include <unordered_set>

namespace dipc {

namespace {
// PETSc log events (registered once per process) and a scope timer that feeds both them and
// the EvaluationTimes counters.
struct Events {
  PetscLogEvent energy, gradient, hessian, validity;
};
const Events& events() {
  static Events e = [] {
    Events r{};
    PetscClassId id;
    PetscClassIdRegister("dipc", &id);
    PetscLogEventRegister("dipcEnergy", id, &r.energy);
    PetscLogEventRegister("dipcGradient", id, &r.gradient);
    PetscLogEventRegister("dipcHessian", id, &r.hessian);
    PetscLogEventRegister("dipcValidity", id, &r.validity);
    return r;
  }();
  return e;
}
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

IncrementalPotential::~IncrementalPotential() {
  VecDestroy(&x_local_);
  VecDestroy(&g_local_);
  VecDestroy(&p_local_);
  VecDestroy(&dirichlet_global_);
}

PetscErrorCode IncrementalPotential::setup(const DistributedMesh& mesh, std::vector<std::unique_ptr<Form>> forms,
                                           std::vector<char> dirichlet_dof) {
  PetscFunctionBeginUser;
  comm_ = mesh.comm;
  mesh_ = &mesh;
  forms_ = std::move(forms);
  dirichlet_dof_ = std::move(dirichlet_dof);
  num_owned_dofs_ = 3 * mesh.num_owned_nodes;
  local_to_global_ = mesh.local_to_global;
  PetscCall(exchange_.setup(mesh, 3));
  // Prescribed dofs as a distributed field, so that the flags of extra nodes can be gathered.
  PetscCall(exchange_.create_global_vec(&dirichlet_global_));
  PetscScalar* d;
  PetscCall(VecGetArray(dirichlet_global_, &d));
  for (int k = 0; k < num_owned_dofs_; ++k) d[k] = dirichlet_dof_[k] ? 1.0 : 0.0;
  PetscCall(VecRestoreArray(dirichlet_global_, &d));
  PetscCall(exchange_.create_local_vec(&x_local_));
  PetscCall(VecDuplicate(x_local_, &g_local_));
  PetscCall(VecDuplicate(x_local_, &p_local_));
  PetscCall(rebuild_pattern());
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

PetscErrorCode IncrementalPotential::rebuild_pattern() {
  PetscFunctionBeginUser;
  rows_.clear(), cols_.clear(), form_offset_.clear(), pattern_versions_.clear();
  for (auto& form : forms_) {
    std::vector<PetscInt> r, c;
    form->coo_pattern(&r, &c);
    form_offset_.push_back(rows_.size());
    pattern_versions_.push_back(form->pattern_version());
    rows_.insert(rows_.end(), r.begin(), r.end());
    cols_.insert(cols_.end(), c.begin(), c.end());
  }
  form_offset_.push_back(rows_.size());

  std::unordered_set<PetscInt> prescribed;
  for (std::size_t n = 0; n < local_to_global_.size(); ++n)
    for (int c = 0; c < 3; ++c)
      if (dirichlet_dof_[3 * n + c]) prescribed.insert(static_cast<PetscInt>(3 * local_to_global_[n] + c));
  eliminated_.clear();
  if (!prescribed.empty())
    for (std::size_t k = 0; k < rows_.size(); ++k)
      if (prescribed.count(rows_[k]) || prescribed.count(cols_[k])) eliminated_.push_back(k);
  dirichlet_diagonal_begin_ = rows_.size();
  for (int k = 0; k < num_owned_dofs_; ++k)
    if (dirichlet_dof_[k]) {
      const PetscInt dof = static_cast<PetscInt>(3 * mesh_->node_offset + k);
      rows_.push_back(dof);
      cols_.push_back(dof);
    }
  values_.assign(rows_.size(), 0.0);
  if (J_) {
    // MatSetPreallocationCOO may reorder the index arrays it is given: pass copies.
    const double start = MPI_Wtime();
    std::vector<PetscInt> r = rows_, c = cols_;
    PetscCall(MatSetPreallocationCOO(J_, static_cast<PetscCount>(r.size()), r.data(), c.data()));
    times_.preallocation += MPI_Wtime() - start;
    ++times_.preallocations;
  }
  PetscFunctionReturn(0);
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
  PetscCall(rebuild_pattern());
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
  ScopedEvent timer(events().energy, &times_.energy);
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
  const PetscScalar* xl;
  PetscCall(VecGetArrayRead(x_local_, &xl));
  const std::size_t nf = forms_.size();
  std::vector<double> local(nf + 1, 0.0), total(nf + 1);
  for (std::size_t f = 0; f < nf; ++f)
    if (!forms_[f]->value(xl, &local[f])) local[nf] = 1.0;
  PetscCall(VecRestoreArrayRead(x_local_, &xl));
  PetscCallMPI(MPI_Allreduce(local.data(), total.data(), static_cast<int>(nf + 1), MPI_DOUBLE, MPI_SUM, comm_));
  values->assign(total.begin(), total.begin() + nf);
  if (total[nf] > 0)
    for (double& v : *values) v = PETSC_INFINITY;
  PetscFunctionReturn(0);
}

PetscErrorCode IncrementalPotential::partial_gradient(Vec x, Vec g, const std::function<bool(const Form&)>& include) {
  PetscFunctionBeginUser;
  PetscCall(gather(x));
  PetscCall(VecZeroEntries(g_local_));
  const PetscScalar* xl;
  PetscScalar* gl;
  PetscCall(VecGetArrayRead(x_local_, &xl));
  PetscCall(VecGetArray(g_local_, &gl));
  bool ok = true;
  for (auto& form : forms_)
    if (!include || include(*form)) ok = form->gradient(xl, gl) && ok;
  PetscCall(VecRestoreArray(g_local_, &gl));
  PetscCall(VecRestoreArrayRead(x_local_, &xl));
  PetscCheck(ok, PETSC_COMM_SELF, PETSC_ERR_PLIB, "gradient requested at an inverted state");
  PetscCall(VecZeroEntries(g));
  PetscCall(exchange_.add_to_global(g_local_, g));
  PetscScalar* ga;
  PetscCall(VecGetArray(g, &ga));
  for (int k = 0; k < num_owned_dofs_; ++k)
    if (dirichlet_dof_[k]) ga[k] = 0;
  PetscCall(VecRestoreArray(g, &ga));
  PetscFunctionReturn(0);
}

PetscErrorCode IncrementalPotential::gradient(Vec x, Vec g) {
  PetscFunctionBeginUser;
  ScopedEvent timer(events().gradient, &times_.gradient);
  PetscCall(partial_gradient(x, g, {}));
  PetscFunctionReturn(0);
}

PetscErrorCode IncrementalPotential::hessian(Vec x, Mat J) {
  PetscFunctionBeginUser;
  ScopedEvent timer(events().hessian, &times_.hessian);
  PetscCheck(J == J_, comm_, PETSC_ERR_ARG_WRONG, "hessian() needs the matrix made by create_matrix()");
  PetscCall(gather(x));
  const PetscScalar* xl;
  PetscCall(VecGetArrayRead(x_local_, &xl));
  for (auto& form : forms_) form->update_pattern(xl);
  int changed = pattern_changed() ? 1 : 0, any = 0;
  PetscCallMPI(MPI_Allreduce(&changed, &any, 1, MPI_INT, MPI_MAX, comm_));
  if (any) PetscCall(rebuild_pattern());
  bool ok = true;
  for (std::size_t f = 0; f < forms_.size(); ++f)
    ok = forms_[f]->hessian(xl, values_.data() + form_offset_[f]) && ok;
  PetscCall(VecRestoreArrayRead(x_local_, &xl));
  PetscCheck(ok, PETSC_COMM_SELF, PETSC_ERR_PLIB, "Hessian requested at an inverted state");
  for (std::size_t k : eliminated_) values_[k] = 0;
  for (std::size_t k = dirichlet_diagonal_begin_; k < values_.size(); ++k) values_[k] = 1;
  const double insert_start = MPI_Wtime();
  PetscCall(MatSetValuesCOO(J, values_.data(), INSERT_VALUES));
  times_.coo_insert += MPI_Wtime() - insert_start;
  PetscFunctionReturn(0);
}

PetscErrorCode IncrementalPotential::refresh_pattern(Vec x, PetscBool* changed) {
  PetscFunctionBeginUser;
  PetscCall(gather(x));
  const PetscScalar* xl;
  PetscCall(VecGetArrayRead(x_local_, &xl));
  for (auto& form : forms_) form->update_pattern(xl);
  PetscCall(VecRestoreArrayRead(x_local_, &xl));
  int local = pattern_changed() ? 1 : 0, any = 0;
  PetscCallMPI(MPI_Allreduce(&local, &any, 1, MPI_INT, MPI_MAX, comm_));
  *changed = any ? PETSC_TRUE : PETSC_FALSE;
  if (any) J_ = nullptr;  // the caller replaces the matrix: create_matrix() rebuilds the pattern
  PetscFunctionReturn(0);
}

PetscErrorCode IncrementalPotential::is_valid(Vec x, PetscBool* valid) {
  PetscFunctionBeginUser;
  ScopedEvent timer(events().validity, &times_.validity);
  PetscCall(gather(x));
  const PetscScalar* xl;
  PetscCall(VecGetArrayRead(x_local_, &xl));
  int ok = 1;
  for (auto& form : forms_) ok = ok && form->is_valid(xl);
  PetscCall(VecRestoreArrayRead(x_local_, &xl));
  int all = 0;
  PetscCallMPI(MPI_Allreduce(&ok, &all, 1, MPI_INT, MPI_MIN, comm_));
  *valid = all ? PETSC_TRUE : PETSC_FALSE;
  PetscFunctionReturn(0);
}

PetscErrorCode IncrementalPotential::prepare_segment(Vec x, Vec p) {
  PetscFunctionBeginUser;
  const double start = MPI_Wtime();
  // Forms may ask for more nodes once they see the segment; then everything is gathered again
  // over the extended node list. Every rank takes part in the rebuild if any rank needs it.
  PetscCall(gather(x));
  PetscCall(exchange_.to_local(p, p_local_));
  int changed = 0;
  {
    const PetscScalar *xl, *pl;
    PetscCall(VecGetArrayRead(x_local_, &xl));
    PetscCall(VecGetArrayRead(p_local_, &pl));
    for (auto& form : forms_) changed = form->update_extra_nodes(xl, pl) || changed;
    PetscCall(VecRestoreArrayRead(p_local_, &pl));
    PetscCall(VecRestoreArrayRead(x_local_, &xl));
  }
  int any = 0;
  PetscCallMPI(MPI_Allreduce(&changed, &any, 1, MPI_INT, MPI_MAX, comm_));
  if (any) {
    PetscCall(rebuild_exchange());
    PetscCall(gather(x));
    PetscCall(exchange_.to_local(p, p_local_));
  }
  const PetscScalar *xl, *pl;
  PetscCall(VecGetArrayRead(x_local_, &xl));
  PetscCall(VecGetArrayRead(p_local_, &pl));
  for (auto& form : forms_) form->prepare_segment(xl, pl);
  PetscCall(VecRestoreArrayRead(p_local_, &pl));
  PetscCall(VecRestoreArrayRead(x_local_, &xl));
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
  const double start = MPI_Wtime();
  const PetscScalar *xl, *pl;
  PetscCall(VecGetArrayRead(x_local_, &xl));
  PetscCall(VecGetArrayRead(p_local_, &pl));
  double a = 1.0;
  for (auto& form : forms_) a = std::min(a, form->max_step(xl, pl));
  PetscCall(VecRestoreArrayRead(p_local_, &pl));
  PetscCall(VecRestoreArrayRead(x_local_, &xl));
  PetscCallMPI(MPI_Allreduce(&a, alpha, 1, MPI_DOUBLE, MPI_MIN, comm_));
  times_.max_step += MPI_Wtime() - start;
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
