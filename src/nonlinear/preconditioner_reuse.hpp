// PreconditionerReuse: keeps the linear solver's preconditioner (the BoomerAMG hierarchy) across
// Newton iterations and time steps for as long as that is cheaper than rebuilding it
// (-dipc_pc_reuse). On a GPU the AMG setup costs as much as 40 CG iterations at 1M elements
// (README "GPU"), while consecutive Hessians of a time-stepping run differ little.
//
// Policy. The decision uses only counts, never clocks, so that two runs of the same input on
// the same ranks take the same decisions and give bit-identical results. Costs are in units of
// one CG iteration: a rebuild costs S = -dipc_pc_reuse_setup_cost (default 40 with a device
// matrix, where one BoomerAMG setup takes about as long as 40 CG iterations on an H100 at 1M
// elements; 5 otherwise: 4 to 6 on one CPU core at 20K elements, 9 to 10 on the shipped
// scenes of a few hundred, README "GPU"), and a linear solve its k CG
// iterations (the same on every rank). A rebuild starts a cycle; the cycle's Newton iterations
// cost C_0 = S + k_0 and C_i = k_i (i = 1 … n). The cycle's average A_n = (C_0 + … + C_n) /
// (n + 1) falls while the old hierarchy still preconditions well and rises once the solves
// lengthen. The long-run cost per iteration of a repeated cycle is smallest when the cycle ends
// as soon as the latest cost exceeds the average so far (the renewal-reward argument behind
// "replace when the marginal cost reaches the average"), so the next iteration rebuilds when
// C_n > A_n.
//
// Always rebuilt: the first solve, a new Hessian pattern, and the solve after one that failed.
// A solve with a reused preconditioner stops after at most max(2 (S + k_0), 10) CG iterations
// (k_0: the solve right after the last rebuild; or -ksp_max_it if smaller), by when a rebuild
// would have paid twice over, so a stale hierarchy cannot blow up a solve; stopping there counts
// as a failed solve. A linear solve that fails with a reused preconditioner does not count
// against -snes_max_linear_solve_fail (NewtonSolver keeps that count, reusing()): Newton takes
// that step (CG's iterate is still a descent direction of an SPD Hessian) and the next
// iteration rebuilds.
#pragma once
#include <petscsnes.h>

namespace dipc {

// The rebuild rule alone, without PETSc (tested in preconditioner_reuse_test.cpp).
class ReuseCycle {
 public:
  // S: what one preconditioner setup costs, in CG iterations.
  explicit ReuseCycle(double setup_cost = 40) : setup_cost_(setup_cost) {}
  // Before a linear solve: true to rebuild the preconditioner for it, false to reuse it.
  bool decide(bool new_pattern);
  // After that solve: its CG iterations and whether it failed.
  void record(long long cg_iterations, bool failed);
  // The most CG iterations a solve with a reused preconditioner may take (after a decision to
  // reuse): max(2 (S + k_0), 10).
  long long reused_solve_limit() const;
  bool rebuilding() const { return rebuilding_; }
  double setup_cost() const { return setup_cost_; }
  double last_cost() const { return last_cost_; }                                            // C_n
  double average_cost() const { return cycle_length_ ? cycle_cost_ / cycle_length_ : 0.0; }  // A_n

 private:
  double setup_cost_;            // S
  bool awaiting_solve_ = false;  // a decision was taken and its solve has not been recorded
  bool rebuilding_ = false;      // the last decision
  double last_cost_ = 0;         // C_n
  double cycle_cost_ = 0;        // C_0 + … + C_n
  long long first_solve_ = 0;    // k_0
  int cycle_length_ = 0;         // n + 1; 0 before the first solve
  bool last_failed_ = false;
};

class PreconditionerReuse {
 public:
  // Reads -dipc_pc_reuse and -dipc_pc_reuse_setup_cost; when on, takes over
  // -snes_lag_preconditioner (refusing both given together; a lag given alone turns a reuse
  // that is on by default off) and hooks the KSP's post-solve to count each solve.
  PetscErrorCode setup(SNES snes);
  // Start of a Newton iteration (SNES update callback), before its Jacobian: decides whether
  // the coming linear solve rebuilds the preconditioner (always for a new pattern).
  PetscErrorCode begin_iteration(SNES snes, bool new_pattern);
  // Rebuilds this policy has decided so far (0 when it is off).
  PetscInt rebuilds() const { return rebuilds_; }
  // The coming linear solve (decided by the last begin_iteration) reuses the preconditioner.
  bool reusing() const { return enabled_ && !cycle_.rebuilding(); }
  bool enabled() const { return enabled_; }

 private:
  static PetscErrorCode after_solve(KSP ksp, Vec rhs, Vec x, void* ctx);

  bool enabled_ = false;
  ReuseCycle cycle_;
  bool counting_ = false;         // between begin_iteration and the end of its solve
  PetscInt user_max_it_ = 10000;  // -ksp_max_it as the user set it
  PetscInt rebuilds_ = 0;
};

}  // namespace dipc
