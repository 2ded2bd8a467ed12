// NewtonSolver: PETSc SNES (newtonls) minimising an IncrementalPotential.
//
//  - objective = E(x), function = ∇E, Jacobian = PSD-projected ∇²E (COO assembly);
//  - line search (line_search.cpp): step capped by the forms' max_step (CCD once contact
//    exists), halved until every element is valid and Armijo holds on E;
//  - convergence: only IPC's velocity criterion ‖p‖∞ / h < tol_v on the Newton direction p
//    (Li et al. 2020, §4.2) ends a solve as converged. PETSc's own small-update and residual
//    tests would end it early with the criterion unmet (a stalled line search passes the
//    small-update test), so they are consulted only when the user gives one of -snes_rtol,
//    -snes_atol, -snes_stol. A solve fails on -snes_max_it, a failed line search or linear
//    solve, a NaN, or a line search stuck below alpha_floor for kStallIterations iterations;
//  - KSP CG + BoomerAMG with the elasticity settings of docs/design.md §1.7 as overridable defaults;
//    -dipc_pc_reuse keeps the preconditioner while that pays (preconditioner_reuse.hpp);
//  - with mean-dilatation elements (unless -dipc_mixed_solve 0) the forms keep the volumetric
//    rank-one terms out of the assembled matrix A, and each Newton system H du = -g is solved as
//    the mixed u-p system of mixed_linear_solve.hpp (FGMRES or MINRES). SNES then sees H as a
//    shell operator (A + Bsᵀ Bs), A as the preconditioning matrix, and a KSPPREONLY whose PCSHELL
//    runs that solve; the report counts its Krylov iterations as the linear iterations;
//    -dipc_pc_reuse does not apply to it.
//  - a stop request (set_stop_check) is asked once per Newton iteration and ends the solve at
//    once, reported as NewtonReport::stopped rather than as a failure;
//  - -dipc_contact_exact_hessian: from a solve's third iteration on, an iteration whose contact
//    active set is the last one's (no new pattern, no remap) assembles the contact pairs'
//    Hessians unprojected. Each pair's PSD projection keeps Newton's direction a descent
//    direction while the active set moves, but once it has settled it leaves Newton converging
//    only linearly (|p| shrank by about 0.6 per iteration on the stack's heavy steps,
//    docs/performance.md "The exact contact Hessian once the active set settles"); the exact
//    Hessian converges quadratically where the total Hessian is positive definite, as it is near
//    a minimiser. Where it is not, CG fails (negative curvature) or returns no descent direction
//    (that direction is dropped without moving, and the preconditioner is rebuilt), or the line
//    search has to cut the step (which stands): after the k-th such failure of a solve the next
//    2^k iterations project, then the exact Hessian is tried again. On by default; not with the
//    mixed solve, nor in the retries of a step that failed (set_retrying: the projected Hessian
//    is the robust path, and a fast impact at 100 m/s that failed a first attempt reached states
//    with the exact Hessian from which no retry could go on).
#pragma once
#include <petscsnes.h>

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "assembly/device_matrix.hpp"
#include "nonlinear/mixed_linear_solve.hpp"
#include "nonlinear/preconditioner_reuse.hpp"
#include "potential/incremental_potential.hpp"

namespace dipc {

struct NewtonReport {
  PetscInt iterations = 0;
  PetscInt linear_iterations = 0;
  PetscInt preconditioner_rebuilds = 0;  // decided by -dipc_pc_reuse (0 when it is off)
  double min_alpha = 1.0;                // smallest accepted line-search step of the solve
  double min_alpha_ccd = 1.0;            // smallest collision-free bound (CCD) on a Newton step
  double step_inf_norm = 0.0;            // ‖p‖∞ of the last Newton direction
  PetscInt exact_hessian_iterations = 0;  // iterations with unprojected contact Hessians
  PetscInt exact_hessian_fallbacks = 0;   // of them, those that failed (see above)
  SNESConvergedReason reason = SNES_CONVERGED_ITERATING;
  std::string ended_by;  // which test ended the solve, in words ("velocity", "max_it", ...)
  bool stopped = false;  // a stop request ended it (reason < 0, but the step did not fail)
};

// The reason a stop request gives SNES. PETSc (3.18 to 3.22) has no reason for a user's stop;
// any negative one ends SNESSolve, and NewtonReport::stopped, not the reason, tells it apart.
constexpr SNESConvergedReason kStopRequestedReason = SNES_DIVERGED_FUNCTION_COUNT;

// Newton iterations in a row whose accepted line-search step stays below the floor before a
// solve is declared stalled: a few such steps happen when surfaces first come close (the CCD
// bound is small once), but a run of them means the iterate no longer moves.
constexpr int kStallIterations = 5;

class NewtonSolver {
 public:
  NewtonSolver() = default;
  ~NewtonSolver();
  NewtonSolver(const NewtonSolver&) = delete;
  NewtonSolver& operator=(const NewtonSolver&) = delete;

  // step_length: h (1 for a static solve); velocity_tol: tol_v in length units per second;
  // alpha_floor: see kStallIterations.
  PetscErrorCode setup(MPI_Comm comm, IncrementalPotential* potential, Vec template_vec, double step_length,
                       double velocity_tol, double alpha_floor);
  // The time step h of the next solves (step recovery changes it).
  void set_step_length(double h) { ls_.step_length = h; }
  // The retries of a scene step that failed an attempt (StepRecovery) solve conservatively: every
  // iteration projects the contact Hessian, whatever -dipc_contact_exact_hessian says, and CG
  // stops at a relative residual 10 times below -ksp_rtol (`balanced`'s 1e-3 failed the
  // extremes' dhat_1e-7 on 2 ranks, which 1e-4 ran). Collective in effect: every rank retries.
  PetscErrorCode set_retrying(bool retrying);
  // Collective check, asked at the start of every Newton iteration (before the Hessian and the
  // linear solve) on every rank; true on all ranks ends the solve as stopped. Empty: never.
  void set_stop_check(std::function<bool()> check) { ls_.stop_requested = std::move(check); }
  // The -snes_* options the user gave (command line or options file), "-name value" each: they
  // are honoured, and the run header names them.
  const std::vector<std::string>& user_snes_options() const { return user_snes_options_; }
  // Minimises E starting from x (overwritten with the minimiser). A solve that does not
  // converge is reported in NewtonReport::reason, not as an error.
  PetscErrorCode solve(Vec x, NewtonReport* report);
  SNES snes() const { return snes_; }
  // The assembled matrix (with the mixed solve: A, the Hessian without its volumetric terms).
  Mat jacobian() const { return J_; }
  bool mixed_solve() const { return mixed_ != nullptr; }

  // Line-search state shared with the callbacks in line_search.cpp.
  struct LineSearchContext {
    IncrementalPotential* potential = nullptr;
    double armijo = 1e-4;  // sufficient-decrease constant c in E(x+αp) ≤ E + cα∇E·p
    double min_alpha = 1.0;
    double min_alpha_ccd = 1.0;
    double direction_inf_norm = 0;
    double step_length = 1.0;
    double velocity_tol = 0;
    double alpha_floor = 0;
    int small_steps_in_a_row = 0;               // accepted α < alpha_floor, consecutive
    double last_alpha = 1, last_alpha_ccd = 1;  // of the latest line search (stall message)
    int last_invalid_trials = 0;                // its halvings forced by an inverted element
    bool petsc_tests = false;                   // the user asked for PETSc's -snes_rtol/atol/stol tests
    std::function<bool()> stop_requested;       // set_stop_check
    bool stopped = false;                       // the solve was ended by stop_requested
    std::string ended_by;
    // Linear solves that may fail without counting against -snes_max_linear_solve_fail: with a
    // reused preconditioner (preconditioner_reuse.hpp) Newton takes CG's iterate so far (a
    // descent direction) and the next iteration rebuilds; an exact contact Hessian's is dropped
    // and the next iterations project.
    bool failure_forgiven = false;  // this iteration's solve is such a one
    PetscInt forgiven = 0;          // such solves that failed, this SNESSolve
    bool exact_hessian = false;     // this iteration's contact Hessians are unprojected
    PetscInt exact_iterations = 0;  // such iterations, this SNESSolve
    PetscInt exact_failures = 0;    // such iterations that failed (below), this SNESSolve
    bool exact_failed = false;      // the last one failed: its solve, or its step was cut
    PetscInt exact_resume = 2;      // the first iteration that may take the exact Hessian
    bool discarded = false;         // the last (exact Hessian's) solve failed: its direction not taken
  };

 private:
  PetscErrorCode set_default_options();
  PetscErrorCode record_user_snes_options();
  PetscErrorCode attach_near_null_space(Vec x);
  static PetscErrorCode update_callback(SNES snes, PetscInt iteration);
  static PetscErrorCode hessian_callback(SNES snes, Vec x, Mat J, Mat P, void* ctx);
  PetscErrorCode setup_mixed_solve();
  static PetscErrorCode mixed_setup(PC pc);
  static PetscErrorCode mixed_apply(PC pc, Vec r, Vec du);
  static PetscErrorCode newton_matrix_multiply(Mat H, Vec u, Vec y);

  SNES snes_ = nullptr;
  Mat J_ = nullptr;
  Vec r_ = nullptr;
  LineSearchContext ls_;
  PreconditionerReuse pc_reuse_;
  bool exact_contact_hessian_ = false;  // -dipc_contact_exact_hessian (not with the mixed solve)
  bool retrying_ = false;               // set_retrying
  PetscReal user_rtol_ = 1e-8;          // -ksp_rtol as the user (or the preset) set it
  PetscInt user_max_failures_ = 1;      // -snes_max_linear_solve_fail as the user set it
  std::vector<std::string> user_snes_options_;
  std::unique_ptr<MixedLinearSolve> mixed_;  // null unless the mixed solve is on
  Mat newton_matrix_ = nullptr;              // with it: the shell H = A + Bsᵀ Bs
  PetscInt mixed_iterations_ = 0;            // the mixed solve's Krylov iterations so far
};

// The line search and convergence test installed by NewtonSolver (line_search.cpp).
PetscErrorCode ipc_line_search(SNESLineSearch ls, void* ctx);
PetscErrorCode velocity_convergence_test(SNES snes, PetscInt it, PetscReal xnorm, PetscReal snorm, PetscReal fnorm,
                                         SNESConvergedReason* reason, void* ctx);

}  // namespace dipc
