// PreconditionerReuse: keeps the linear solver's preconditioner (the BoomerAMG hierarchy) across
// Newton iterations and time steps for as long as that is cheaper than rebuilding it
// (-dipc_pc_reuse). On a GPU the AMG setup costs as much as 30–40 CG iterations at 1M elements
// (README "GPU"), while consecutive Hessians of a time-stepping run differ little.
//
// Policy. A rebuild starts a cycle. Let T_0, T_1, …, T_n be the wall times of the cycle's
// Newton iterations from the Jacobian to the end of the linear solve (T_0 carries the setup).
// The cycle's average A_n = (T_0 + … + T_n) / (n + 1) falls while the old hierarchy still
// preconditions well and rises once the solves lengthen. The long-run time per iteration of a
// repeated cycle is smallest when the cycle ends as soon as the latest cost exceeds the average
// so far (the renewal-reward argument behind "replace when the marginal cost reaches the
// average"), so the next iteration rebuilds when T_n > A_n. Measured times make the rule
// self-tuning (CPU or GPU, any preconditioner) at the price of run-to-run differences in the
// Newton path within the Newton tolerance; the decision uses the slowest rank's times, so all
// ranks agree.
//
// Always rebuilt: the first solve, a new Hessian pattern, and the solve after one that failed.
// A linear solve that fails with a reused preconditioner does not count against
// -snes_max_linear_solve_fail: Newton takes that step (CG's iterate is still a descent
// direction of an SPD Hessian) and the next iteration rebuilds.
#pragma once
#include <petscsnes.h>

namespace dipc {

// The rebuild rule alone, without PETSc (tested in preconditioner_reuse_test.cpp).
class ReuseCycle {
 public:
  // Before a linear solve: true to rebuild the preconditioner for it, false to reuse it.
  bool decide(bool new_pattern);
  // After that solve: its Jacobian + solve wall time and whether it failed.
  void record(double seconds, bool failed);
  bool rebuilding() const { return rebuilding_; }
  double last_seconds() const { return last_time_; }
  double average_seconds() const { return cycle_length_ ? cycle_time_ / cycle_length_ : 0.0; }

 private:
  bool awaiting_solve_ = false;  // a decision was taken and its solve has not been recorded
  bool rebuilding_ = false;      // the last decision
  double last_time_ = 0;         // T_n
  double cycle_time_ = 0;        // T_0 + … + T_n
  int cycle_length_ = 0;         // n + 1; 0 before the first solve
  bool last_failed_ = false;
};

class PreconditionerReuse {
 public:
  // Reads -dipc_pc_reuse; when set, takes over -snes_lag_preconditioner (refusing both) and
  // hooks the KSP's post-solve to time each solve.
  PetscErrorCode setup(SNES snes);
  // Start of a Newton iteration (SNES update callback), before its Jacobian: decides whether
  // the coming linear solve rebuilds the preconditioner. `iteration` is SNES's iteration
  // number (0 starts a new nonlinear solve).
  PetscErrorCode begin_iteration(SNES snes, PetscInt iteration, bool new_pattern);
  // Rebuilds this policy has decided so far (0 when it is off).
  PetscInt rebuilds() const { return rebuilds_; }

 private:
  static PetscErrorCode after_solve(KSP ksp, Vec rhs, Vec x, void* ctx);

  bool enabled_ = false;
  ReuseCycle cycle_;
  bool timing_ = false;             // between begin_iteration and the end of its solve
  double iteration_start_ = 0;
  PetscInt user_max_failures_ = 1;  // -snes_max_linear_solve_fail as the user set it
  PetscInt reuse_failures_ = 0;     // failed solves with a reused preconditioner, this SNESSolve
  PetscInt rebuilds_ = 0;
};

}  // namespace dipc
