// IncrementalPotential: E(x) = Σ forms, evaluated on distributed PETSc Vecs.
//
// Per evaluation it gathers x to this rank's local nodes once (GhostExchange), lets every
// form work on local arrays, reduces the energy over ranks once and scatters gradient
// contributions of ghost nodes back to their owners once. The Hessian is assembled with
// MatSetValuesCOO on the concatenated COO patterns of all forms, preallocated once.
//
// Dirichlet dofs are eliminated symmetrically: their gradient entries are zero, their Hessian
// rows and columns are zero with a unit diagonal, so Newton never moves them and CG sees an
// SPD matrix. The time integrator sets their prescribed values in x before each solve.
#pragma once
#include <petscmat.h>

#include <memory>
#include <vector>

#include "nonlinear/form.hpp"
#include "partition/ghost_exchange.hpp"

namespace dipc {

// Wall time spent in each kind of evaluation on this rank (seconds), and PETSc log events
// of the same names so -log_view shows them.
struct EvaluationTimes {
  double energy = 0, gradient = 0, hessian = 0, validity = 0;
  double coo_insert = 0;  // MatSetValuesCOO alone (part of hessian)
};

class IncrementalPotential {
 public:
  IncrementalPotential() = default;
  ~IncrementalPotential();
  IncrementalPotential(const IncrementalPotential&) = delete;
  IncrementalPotential& operator=(const IncrementalPotential&) = delete;

  // dirichlet_dof: 3 flags per local node (owned and ghost) marking prescribed dofs.
  PetscErrorCode setup(MPI_Comm comm, const DistributedMesh& mesh, const GhostExchange& exchange,
                       std::vector<std::unique_ptr<Form>> forms, std::vector<char> dirichlet_dof);
  // A matrix with the combined COO pattern preallocated (type from -mat_type, default aij).
  PetscErrorCode create_matrix(Mat* J);

  // E(x) over all ranks; +inf when x is not admissible (inverted element).
  PetscErrorCode objective(Vec x, PetscReal* energy);
  PetscErrorCode gradient(Vec x, Vec g);
  PetscErrorCode hessian(Vec x, Mat J);
  // True on every rank iff every form accepts x on every rank.
  PetscErrorCode is_valid(Vec x, PetscBool* valid);
  // min over forms and ranks of the admissible step fraction along p.
  PetscErrorCode max_step(Vec x, Vec p, PetscReal* alpha);
  // Passes the predicted positions x̂ (distributed) to every form.
  PetscErrorCode begin_step(Vec x_hat);

  const std::vector<std::unique_ptr<Form>>& forms() const { return forms_; }
  const std::vector<char>& dirichlet_dof() const { return dirichlet_dof_; }
  PetscInt num_hessian_entries() const { return static_cast<PetscInt>(values_.size()); }
  const EvaluationTimes& times() const { return times_; }

 private:
  PetscErrorCode gather(Vec x);  // x -> x_local_

  MPI_Comm comm_ = MPI_COMM_NULL;
  const GhostExchange* exchange_ = nullptr;
  std::vector<std::unique_ptr<Form>> forms_;
  std::vector<char> dirichlet_dof_;
  int num_owned_dofs_ = 0;
  Vec x_local_ = nullptr, g_local_ = nullptr, p_local_ = nullptr;
  std::vector<PetscInt> rows_, cols_;   // combined pattern (forms, then Dirichlet diagonal)
  std::vector<std::size_t> form_offset_;  // start of each form's block in values_
  std::vector<std::size_t> eliminated_;   // entries in a Dirichlet row or column
  std::size_t dirichlet_diagonal_begin_ = 0;
  std::vector<PetscScalar> values_;
  EvaluationTimes times_;
};

}  // namespace dipc
