// NewtonSolver: PETSc SNES (newtonls) minimising an IncrementalPotential.
//
//  - objective = E(x), function = ∇E, Jacobian = PSD-projected ∇²E (COO assembly);
//  - line search (line_search.cpp): step capped by the forms' max_step (CCD once contact
//    exists), halved until every element is valid and Armijo holds on E;
//  - convergence: IPC's velocity criterion ‖p‖∞ / h < tol_v on the Newton direction p
//    (Li et al. 2020, §4.2), or PETSc's usual tests (-snes_rtol, -snes_atol, -snes_max_it);
//  - KSP CG + BoomerAMG with the elasticity settings of DESIGN.md §2 as overridable defaults;
//    -dipc_pc_reuse keeps the preconditioner while that pays (preconditioner_reuse.hpp).
#pragma once
#include <petscsnes.h>

#include "nonlinear/device_matrix.hpp"
#include "nonlinear/incremental_potential.hpp"
#include "nonlinear/preconditioner_reuse.hpp"

namespace dipc {

struct NewtonReport {
  PetscInt iterations = 0;
  PetscInt linear_iterations = 0;
  PetscInt preconditioner_rebuilds = 0;  // decided by -dipc_pc_reuse (0 when it is off)
  double min_alpha = 1.0;       // smallest accepted line-search step of the solve
  double min_alpha_ccd = 1.0;   // smallest collision-free bound (CCD) on a Newton step
  double step_inf_norm = 0.0;   // ‖p‖∞ of the last Newton direction
  SNESConvergedReason reason = SNES_CONVERGED_ITERATING;
};

class NewtonSolver {
 public:
  NewtonSolver() = default;
  ~NewtonSolver();
  NewtonSolver(const NewtonSolver&) = delete;
  NewtonSolver& operator=(const NewtonSolver&) = delete;

  // step_length: h (1 for a static solve); velocity_tol: tol_v in length units per second.
  PetscErrorCode setup(MPI_Comm comm, IncrementalPotential* potential, Vec template_vec,
                       double step_length, double velocity_tol);
  // Minimises E starting from x (overwritten with the minimiser). A solve that does not
  // converge is reported in NewtonReport::reason, not as an error.
  PetscErrorCode solve(Vec x, NewtonReport* report);
  SNES snes() const { return snes_; }
  Mat jacobian() const { return J_; }

  // Line-search state shared with the callbacks in line_search.cpp.
  struct LineSearchContext {
    IncrementalPotential* potential = nullptr;
    double armijo = 1e-4;          // sufficient-decrease constant c in E(x+αp) ≤ E + cα∇E·p
    double min_alpha = 1.0;
    double min_alpha_ccd = 1.0;
    double direction_inf_norm = 0;
    double step_length = 1.0;
    double velocity_tol = 0;
  };

 private:
  PetscErrorCode set_default_options();
  PetscErrorCode attach_near_null_space(Vec x);
  static PetscErrorCode update_callback(SNES snes, PetscInt iteration);

  SNES snes_ = nullptr;
  Mat J_ = nullptr;
  Vec r_ = nullptr;
  LineSearchContext ls_;
  PreconditionerReuse pc_reuse_;
};



// The line search and convergence test installed by NewtonSolver (line_search.cpp).
PetscErrorCode ipc_line_search(SNESLineSearch ls, void* ctx);
PetscErrorCode velocity_convergence_test(SNES snes, PetscInt it, PetscReal xnorm, PetscReal snorm,
                                         PetscReal fnorm, SNESConvergedReason* reason, void* ctx);

}  // namespace dipc
