#include "nonlinear/preconditioner_reuse.hpp"

namespace dipc {

// Rebuild when nothing is known about the current preconditioner (first solve; or the last
// decision's solve never ran because its iteration stopped early), for a new pattern, after a
// failed solve, and when the latest cost exceeds the cycle's average: T_n > A_n.
bool ReuseCycle::decide(bool new_pattern) {
  rebuilding_ = new_pattern || cycle_length_ == 0 || awaiting_solve_ || last_failed_ ||
                last_time_ * cycle_length_ > cycle_time_;
  if (rebuilding_) {
    cycle_time_ = 0;
    cycle_length_ = 0;
  }
  awaiting_solve_ = true;
  return rebuilding_;
}

void ReuseCycle::record(double seconds, bool failed) {
  awaiting_solve_ = false;
  last_time_ = seconds;
  cycle_time_ += seconds;
  ++cycle_length_;
  last_failed_ = failed;
}

PetscErrorCode PreconditionerReuse::setup(SNES snes) {
  PetscFunctionBeginUser;
  MPI_Comm comm = PetscObjectComm(reinterpret_cast<PetscObject>(snes));
  PetscBool flag = PETSC_FALSE, lag_set;
  // Read inside an options block so that -help lists it with the run options.
  PetscOptionsBegin(comm, nullptr, "dipc preconditioner reuse", "SNES");
  PetscCall(PetscOptionsBool("-dipc_pc_reuse", "Keep the preconditioner across Newton iterations while that is cheaper",
                             "", flag, &flag, nullptr));
  PetscOptionsEnd();
  enabled_ = flag;
  if (!enabled_) PetscFunctionReturn(0);
  PetscCall(PetscOptionsHasName(nullptr, nullptr, "-snes_lag_preconditioner", &lag_set));
  PetscCheck(!lag_set, comm, PETSC_ERR_ARG_INCOMP,
             "-dipc_pc_reuse decides when to rebuild the preconditioner itself; drop -snes_lag_preconditioner");
  PetscCall(SNESGetMaxLinearSolveFailures(snes, &user_max_failures_));
  KSP ksp;
  PetscCall(SNESGetKSP(snes, &ksp));
  PetscCall(KSPSetPostSolve(ksp, after_solve, this));
  PetscFunctionReturn(0);
}

PetscErrorCode PreconditionerReuse::begin_iteration(SNES snes, PetscInt iteration, bool new_pattern) {
  PetscFunctionBeginUser;
  if (!enabled_) PetscFunctionReturn(0);
  if (iteration == 0) reuse_failures_ = 0;  // SNESSolve has reset its failure count
  const bool rebuild = cycle_.decide(new_pattern);
  if (rebuild) ++rebuilds_;
  PetscCall(PetscInfo(snes, "dipc_pc_reuse: %s the preconditioner (last solve %g s, cycle average %g s)\n",
                      rebuild ? "rebuilding" : "reusing", cycle_.last_seconds(), cycle_.average_seconds()));
  // Lag -2: rebuild for this Jacobian, then reuse; -1: reuse (SNESComputeJacobian applies it).
  PetscCall(SNESSetLagPreconditioner(snes, rebuild ? -2 : -1));
  // A failure with a reused preconditioner gets one extra allowance (see the header); the
  // stop condition is then "failures with fresh preconditioners >= the user's maximum".
  PetscCall(SNESSetMaxLinearSolveFailures(snes, user_max_failures_ + reuse_failures_ + (rebuild ? 0 : 1)));
  timing_ = true;
  iteration_start_ = MPI_Wtime();
  PetscFunctionReturn(0);
}

// KSP post-solve hook: times the iteration's Jacobian + solve on the slowest rank.
PetscErrorCode PreconditionerReuse::after_solve(KSP ksp, Vec, Vec, void* ctx) {
  PetscFunctionBeginUser;
  auto* self = static_cast<PreconditionerReuse*>(ctx);
  if (!self->timing_) PetscFunctionReturn(0);  // a solve outside SNES's iterations
  self->timing_ = false;
  const double local = MPI_Wtime() - self->iteration_start_;
  double slowest;
  PetscCallMPI(MPI_Allreduce(&local, &slowest, 1, MPI_DOUBLE, MPI_MAX, PetscObjectComm(reinterpret_cast<PetscObject>(ksp))));
  KSPConvergedReason reason;
  PetscCall(KSPGetConvergedReason(ksp, &reason));
  self->cycle_.record(slowest, reason < 0);
  if (reason < 0 && !self->cycle_.rebuilding()) ++self->reuse_failures_;
  PetscFunctionReturn(0);
}

}  // namespace dipc
