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
}

PetscErrorCode IncrementalPotential::setup(MPI_Comm comm, const DistributedMesh& mesh,
                                           const GhostExchange& exchange,
                                           std::vector<std::unique_ptr<Form>> forms,
                                           std::vector<char> dirichlet_dof) {
  PetscFunctionBeginUser;
  comm_ = comm;
  exchange_ = &exchange;
  forms_ = std::move(forms);
  dirichlet_dof_ = std::move(dirichlet_dof);
  num_owned_dofs_ = 3 * mesh.num_owned_nodes;
  PetscCall(exchange.create_local_vec(&x_local_));
  PetscCall(VecDuplicate(x_local_, &g_local_));
  PetscCall(VecDuplicate(x_local_, &p_local_));

  rows_.clear(), cols_.clear(), form_offset_.clear();
  for (auto& form : forms_) {
    std::vector<PetscInt> r, c;
    form->coo_pattern(&r, &c);
    form_offset_.push_back(rows_.size());
    rows_.insert(rows_.end(), r.begin(), r.end());
    cols_.insert(cols_.end(), c.begin(), c.end());
  }
  form_offset_.push_back(rows_.size());

  std::unordered_set<PetscInt> prescribed;
  for (int n = 0; n < mesh.num_local_nodes(); ++n)
    for (int c = 0; c < 3; ++c)
      if (dirichlet_dof_[3 * n + c]) prescribed.insert(static_cast<PetscInt>(3 * mesh.local_to_global[n] + c));
  eliminated_.clear();
  if (!prescribed.empty())
    for (std::size_t k = 0; k < rows_.size(); ++k)
      if (prescribed.count(rows_[k]) || prescribed.count(cols_[k])) eliminated_.push_back(k);
  dirichlet_diagonal_begin_ = rows_.size();
  for (int k = 0; k < num_owned_dofs_; ++k)
    if (dirichlet_dof_[k]) {
      const PetscInt dof = static_cast<PetscInt>(3 * mesh.node_offset + k);
      rows_.push_back(dof);
      cols_.push_back(dof);
    }
  values_.assign(rows_.size(), 0.0);
  PetscFunctionReturn(0);
}

PetscErrorCode IncrementalPotential::create_matrix(Mat* J) {
  PetscFunctionBeginUser;
  PetscCall(MatCreate(comm_, J));
  PetscCall(MatSetSizes(*J, num_owned_dofs_, num_owned_dofs_, PETSC_DETERMINE, PETSC_DETERMINE));
  PetscCall(MatSetBlockSize(*J, 3));
  PetscCall(MatSetType(*J, MATAIJ));
  PetscCall(MatSetFromOptions(*J));
  // MatSetPreallocationCOO may reorder the index arrays it is given: pass copies.
  std::vector<PetscInt> r = rows_, c = cols_;
  PetscCall(MatSetPreallocationCOO(*J, static_cast<PetscCount>(r.size()), r.data(), c.data()));
  PetscCall(MatSetOption(*J, MAT_SPD, PETSC_TRUE));
  PetscFunctionReturn(0);
}

PetscErrorCode IncrementalPotential::gather(Vec x) {
  PetscFunctionBeginUser;
  PetscCall(exchange_->to_local(x, x_local_));
  PetscFunctionReturn(0);
}

PetscErrorCode IncrementalPotential::objective(Vec x, PetscReal* energy) {
  PetscFunctionBeginUser;
  ScopedEvent timer(events().energy, &times_.energy);
  PetscCall(gather(x));
  const PetscScalar* xl;
  PetscCall(VecGetArrayRead(x_local_, &xl));
  double local = 0;
  int admissible = 1;
  for (auto& form : forms_) {
    double e = 0;
    if (!form->value(xl, &e)) admissible = 0;
    local += e;
  }
  PetscCall(VecRestoreArrayRead(x_local_, &xl));
  double in[2] = {local, admissible ? 0.0 : 1.0}, out[2];
  PetscCallMPI(MPI_Allreduce(in, out, 2, MPI_DOUBLE, MPI_SUM, comm_));
  *energy = out[1] > 0 ? PETSC_INFINITY : out[0];
  PetscFunctionReturn(0);
}

PetscErrorCode IncrementalPotential::gradient(Vec x, Vec g) {
  PetscFunctionBeginUser;
  ScopedEvent timer(events().gradient, &times_.gradient);
  PetscCall(gather(x));
  PetscCall(VecZeroEntries(g_local_));
  const PetscScalar* xl;
  PetscScalar* gl;
  PetscCall(VecGetArrayRead(x_local_, &xl));
  PetscCall(VecGetArray(g_local_, &gl));
  bool ok = true;
  for (auto& form : forms_) ok = form->gradient(xl, gl) && ok;
  PetscCall(VecRestoreArray(g_local_, &gl));
  PetscCall(VecRestoreArrayRead(x_local_, &xl));
  PetscCheck(ok, PETSC_COMM_SELF, PETSC_ERR_PLIB, "gradient requested at an inverted state");
  PetscCall(VecZeroEntries(g));
  PetscCall(exchange_->add_to_global(g_local_, g));
  PetscScalar* ga;
  PetscCall(VecGetArray(g, &ga));
  for (int k = 0; k < num_owned_dofs_; ++k)
    if (dirichlet_dof_[k]) ga[k] = 0;
  PetscCall(VecRestoreArray(g, &ga));
  PetscFunctionReturn(0);
}

PetscErrorCode IncrementalPotential::hessian(Vec x, Mat J) {
  PetscFunctionBeginUser;
  ScopedEvent timer(events().hessian, &times_.hessian);
  PetscCall(gather(x));
  const PetscScalar* xl;
  PetscCall(VecGetArrayRead(x_local_, &xl));
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

PetscErrorCode IncrementalPotential::max_step(Vec x, Vec p, PetscReal* alpha) {
  PetscFunctionBeginUser;
  PetscCall(gather(x));
  PetscCall(exchange_->to_local(p, p_local_));
  const PetscScalar *xl, *pl;
  PetscCall(VecGetArrayRead(x_local_, &xl));
  PetscCall(VecGetArrayRead(p_local_, &pl));
  double a = 1.0;
  for (auto& form : forms_) a = std::min(a, form->max_step(xl, pl));
  PetscCall(VecRestoreArrayRead(p_local_, &pl));
  PetscCall(VecRestoreArrayRead(x_local_, &xl));
  PetscCallMPI(MPI_Allreduce(&a, alpha, 1, MPI_DOUBLE, MPI_MIN, comm_));
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

}  // namespace dipc
