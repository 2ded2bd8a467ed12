#include "nonlinear/preconditioner_reuse.hpp"

#include <algorithm>
#include <cmath>

#include "assembly/device_matrix.hpp"
#include "options/dipc_options.hpp"

namespace dipc {

namespace {
// S when -dipc_pc_reuse_setup_cost is not given, in CG iterations (README "GPU"): one BoomerAMG
// setup against one CG iteration, measured with -log_view (PCSetUp per call against KSPSolve
// per CG iteration).
constexpr double kDeviceSetupCost = 40;  // one H100, 1M elements: 0.36 s against 9 ms
constexpr double kHostSetupCost = 5;     // one CPU core: 4-6 at 20K elements, 9-10 below 500
}  // namespace

// Rebuild when nothing is known about the current preconditioner (first solve; or the last
// decision's solve never ran because its iteration stopped early), for a new pattern, after a
// failed solve, and when the latest cost exceeds the cycle's average: C_n > A_n, compared as
// C_n (n + 1) > C_0 + … + C_n.
bool ReuseCycle::decide(bool new_pattern) {
  rebuilding_ = new_pattern || cycle_length_ == 0 || awaiting_solve_ || last_failed_ ||
                last_cost_ * cycle_length_ > cycle_cost_;
  if (rebuilding_) {
    cycle_cost_ = 0;
    cycle_length_ = 0;
  }
  awaiting_solve_ = true;
  return rebuilding_;
}

void ReuseCycle::record(long long cg_iterations, bool failed) {
  awaiting_solve_ = false;
  last_cost_ = static_cast<double>(cg_iterations) + (cycle_length_ == 0 ? setup_cost_ : 0.0);
  if (cycle_length_ == 0) first_solve_ = cg_iterations;
  cycle_cost_ += last_cost_;
  ++cycle_length_;
  last_failed_ = failed;
}

long long ReuseCycle::reused_solve_limit() const {
  return std::max(10LL, static_cast<long long>(std::ceil(2 * (setup_cost_ + first_solve_))));
}

PetscErrorCode PreconditionerReuse::setup(SNES snes) {
  PetscFunctionBeginUser;
  MPI_Comm comm = PetscObjectComm(reinterpret_cast<PetscObject>(snes));
  Mat J;
  PetscCall(SNESGetJacobian(snes, &J, nullptr, nullptr, nullptr));
  // Off unless asked for; the default preset (app/solver_presets.hpp) asks for it, except when
  // the user gave -snes_lag_preconditioner.
  PetscBool flag = PETSC_FALSE, lag_set;
  PetscReal setup_cost = J && matrix_on_device(J) ? kDeviceSetupCost : kHostSetupCost;
  // Read inside an options block so that -help lists them with the run options.
  PetscOptionsBegin(comm, nullptr, "dipc preconditioner reuse", "SNES");
  constexpr const OptionSpec& reuse = dipc_option("-dipc_pc_reuse");
  constexpr const OptionSpec& cost = dipc_option("-dipc_pc_reuse_setup_cost");
  PetscCall(PetscOptionsBool(reuse.name, reuse.help, reuse.manual, flag, &flag, nullptr));
  PetscCall(PetscOptionsReal(cost.name, cost.help, cost.manual, setup_cost, &setup_cost, nullptr));
  PetscOptionsEnd();
  PetscCall(PetscOptionsHasName(nullptr, nullptr, "-snes_lag_preconditioner", &lag_set));
  enabled_ = flag;
  if (!enabled_) PetscFunctionReturn(0);
  cycle_ = ReuseCycle(setup_cost);
  PetscCheck(!lag_set, comm, PETSC_ERR_ARG_INCOMP,
             "-dipc_pc_reuse decides when to rebuild the preconditioner itself; drop -snes_lag_preconditioner");
  KSP ksp;
  PetscCall(SNESGetKSP(snes, &ksp));
  PetscReal rtol, abstol, dtol;
  PetscCall(KSPGetTolerances(ksp, &rtol, &abstol, &dtol, &user_max_it_));
  PetscCall(KSPSetPostSolve(ksp, after_solve, this));
  PetscFunctionReturn(0);
}

PetscErrorCode PreconditionerReuse::begin_iteration(SNES snes, bool new_pattern) {
  PetscFunctionBeginUser;
  if (!enabled_) PetscFunctionReturn(0);
  const bool rebuild = cycle_.decide(new_pattern);
  if (rebuild) ++rebuilds_;
  const PetscInt max_it = rebuild
                              ? user_max_it_
                              : static_cast<PetscInt>(std::min<long long>(user_max_it_, cycle_.reused_solve_limit()));
  PetscCall(PetscInfo(snes,
                      "dipc_pc_reuse: %s the preconditioner (last iteration cost %g, cycle average %g CG "
                      "iterations; setup %g; at most %" PetscInt_FMT " CG iterations)\n",
                      rebuild ? "rebuilding" : "reusing", cycle_.last_cost(), cycle_.average_cost(),
                      cycle_.setup_cost(), max_it));
  // Lag -2: rebuild for this Jacobian, then reuse; -1: reuse (SNESComputeJacobian applies it).
  PetscCall(SNESSetLagPreconditioner(snes, rebuild ? -2 : -1));
  KSP ksp;
  PetscReal rtol, abstol, dtol;
  PetscInt current_max_it;
  PetscCall(SNESGetKSP(snes, &ksp));
  PetscCall(KSPGetTolerances(ksp, &rtol, &abstol, &dtol, &current_max_it));
  PetscCall(KSPSetTolerances(ksp, rtol, abstol, dtol, max_it));
  counting_ = true;
  PetscFunctionReturn(0);
}

// KSP post-solve hook: records the iteration's CG count, the same on every rank.
PetscErrorCode PreconditionerReuse::after_solve(KSP ksp, Vec, Vec, void* ctx) {
  PetscFunctionBeginUser;
  auto* self = static_cast<PreconditionerReuse*>(ctx);
  if (!self->counting_) PetscFunctionReturn(0);  // a solve outside SNES's iterations
  self->counting_ = false;
  PetscInt its;
  KSPConvergedReason reason;
  PetscCall(KSPGetIterationNumber(ksp, &its));
  PetscCall(KSPGetConvergedReason(ksp, &reason));
  self->cycle_.record(its, reason < 0);
  PetscFunctionReturn(0);
}

}  // namespace dipc
