// Directional central differences of a distributed potential (objective, gradient, hessian of
// PETSc Vecs and a Mat, such as IncrementalPotential): the derivative check that scales to
// any mesh and rank count. Both quotients come from central_difference
// (finite_difference.hpp) applied to t -> E(x + t d) and t -> g(x + t d) at t = 0.
#pragma once
#include <petscmat.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "support/finite_difference.hpp"

namespace dipc::test {

struct DirectionalDifferences {
  double slope = 0;          // g(x) . d
  double slope_fd = 0;       // (E(x + eps d) - E(x - eps d)) / (2 eps)
  double hessian_error = 0;  // max |(g(x + eps d) - g(x - eps d)) / (2 eps) - H(x) d|
  double hessian_scale = 0;  // max |H(x) d|
};

// Collective. H receives the Hessian at x. The potential is evaluated at x + eps d and
// x - eps d (energies first, then gradients), so a contact potential's candidates must cover
// that stencil (max_step over it) before the call.
template <class Potential>
PetscErrorCode directional_differences(Potential& potential, Mat H, Vec x, Vec d, double eps,
                                       DirectionalDifferences* out) {
  PetscFunctionBeginUser;
  Vec w, g, Hd;
  PetscCall(VecDuplicate(x, &w));
  PetscCall(VecDuplicate(x, &g));
  PetscCall(VecDuplicate(x, &Hd));
  PetscInt n = 0;
  PetscCall(VecGetLocalSize(x, &n));
  PetscErrorCode status = 0;
  const double t0 = 0;
  const auto energy_along = [&](const double* t, double* energy) {
    PetscReal e = 0;
    if (!status) status = VecWAXPY(w, *t, d, x);
    if (!status) status = potential.objective(w, &e);
    *energy = e;
  };
  central_difference(energy_along, &t0, 1, 1, eps, &out->slope_fd);  // errors: in status
  PetscCall(status);
  PetscCall(potential.gradient(x, g));
  PetscCall(VecDot(g, d, &out->slope));
  const auto gradient_along = [&](const double* t, double* local) {
    const PetscScalar* a = nullptr;
    if (!status) status = VecWAXPY(w, *t, d, x);
    if (!status) status = potential.gradient(w, g);
    if (!status) status = VecGetArrayRead(g, &a);
    if (!status) std::copy(a, a + n, local);
    if (!status) status = VecRestoreArrayRead(g, &a);
  };
  std::vector<double> gradient_fd(n);
  central_difference(gradient_along, &t0, 1, static_cast<int>(n), eps, gradient_fd.data());
  PetscCall(status);
  PetscCall(potential.hessian(x, H));
  PetscCall(MatMult(H, d, Hd));
  PetscCall(VecNorm(Hd, NORM_INFINITY, &out->hessian_scale));
  const PetscScalar* hd;
  double local_error = 0;
  PetscCall(VecGetArrayRead(Hd, &hd));
  for (PetscInt i = 0; i < n; ++i) local_error = std::max(local_error, std::abs(gradient_fd[i] - hd[i]));
  PetscCall(VecRestoreArrayRead(Hd, &hd));
  PetscCallMPI(MPI_Allreduce(&local_error, &out->hessian_error, 1, MPI_DOUBLE, MPI_MAX,
                             PetscObjectComm(reinterpret_cast<PetscObject>(x))));
  for (Vec* v : {&w, &g, &Hd}) PetscCall(VecDestroy(v));
  PetscFunctionReturn(0);
}

}  // namespace dipc::test
