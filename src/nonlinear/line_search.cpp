// The IPC line search (Li et al. 2020, Alg. 1) as a PETSc shell line search, and the
// velocity convergence test.
//
// PETSc's newtonls hands us X (current), F = ∇E(X), Y = the Newton direction with the
// sign convention X_new = X − λY. We take α₀ = min(1, max_step) — the forms' collision-free
// bound — then halve α until the trial state is valid (no inverted element) and satisfies
// Armijo on E. When the predicted decrease is below the round-off of E itself (near
// convergence) Armijo cannot be resolved, so a valid step that does not increase E by more
// than that round-off is accepted.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "logging/log_stages.hpp"
#include "nonlinear/newton_solver.hpp"

namespace dipc {

namespace {

// An exact-Hessian iteration that failed (its linear solve or its line search): the next iterations
// project (newton_solver.cpp, update_callback).
void count_exact_failure(NewtonSolver::LineSearchContext* ctx) {
  ctx->exact_failed = true;
  ++ctx->exact_failures;
}

// Bookkeeping of the linear solve whose direction arrives here (newton_solver.hpp): a failure
// SNES forgave is counted. A solve with the exact contact Hessian that met negative curvature
// (in the matrix or in BoomerAMG) or gave no descent direction is discarded, and the next
// iterations project (newton_solver.hpp). Its direction is not taken even where CG's iterate
// before the negative curvature descends: that iterate can point far off, and taking it cost a
// test solve 10 more Newton iterations than dropping it (exact_hessian_test.cpp). A solve that
// only ran out of iterations (a reused preconditioner's cap) met no negative curvature: its
// descent direction is taken, as with the projected Hessian.
PetscErrorCode settle_linear_solve(SNES snes, NewtonSolver::LineSearchContext* ctx, PetscReal slope) {
  KSP ksp;
  KSPConvergedReason reason;
  PetscFunctionBeginUser;
  PetscCall(SNESGetKSP(snes, &ksp));
  PetscCall(KSPGetConvergedReason(ksp, &reason));
  if (reason < 0 && ctx->failure_forgiven) ++ctx->forgiven;
  ctx->discarded = ctx->exact_hessian && ((reason < 0 && reason != KSP_DIVERGED_ITS) || !(slope < 0));
  ctx->exact_failed = false;
  if (ctx->discarded) {
    count_exact_failure(ctx);
    PetscCall(PetscInfo(snes, "exact contact Hessian: linear solve %s, slope %g; dropped\n",
                        KSPConvergedReasons[reason], (double)slope));
  }
  PetscFunctionReturn(0);
}

// A dropped direction: X stays, and SNES's norms see a zero step (the convergence test skips it).
PetscErrorCode stay_put(SNESLineSearch ls, Vec Y) {
  PetscFunctionBeginUser;
  PetscCall(VecZeroEntries(Y));
  PetscCall(SNESLineSearchSetLambda(ls, 0.0));
  PetscCall(SNESLineSearchComputeNorms(ls));
  PetscFunctionReturn(0);
}

}  // namespace

PetscErrorCode ipc_line_search(SNESLineSearch ls, void* ctx_) {
  EventScope event(log_events().line_search);
  auto* ctx = static_cast<NewtonSolver::LineSearchContext*>(ctx_);
  SNES snes;
  Vec X, F, Y, W, G;
  PetscFunctionBeginUser;
  PetscCall(SNESLineSearchGetSNES(ls, &snes));
  PetscCall(SNESLineSearchGetVecs(ls, &X, &F, &Y, &W, &G));
  PetscCall(VecNorm(Y, NORM_INFINITY, &ctx->direction_inf_norm));

  PetscReal E0, slope;
  PetscCall(VecDot(F, Y, &slope));
  slope = -slope;  // d/dα E(X − αY) at α = 0
  PetscCall(settle_linear_solve(snes, ctx, slope));
  if (ctx->discarded) {  // the next iteration projects (newton_solver.hpp)
    PetscCall(stay_put(ls, Y));
    PetscFunctionReturn(0);
  }
  PetscCall(VecScale(Y, -1.0));  // Y := p, the descent direction (restored below)
  PetscReal alpha;
  // max_step also keeps X and p where the forms evaluate, so every trial below moves only α
  // and scalars between host and device.
  PetscCall(ctx->potential->max_step(X, Y, &alpha));
  PetscCall(ctx->potential->segment_objective(0.0, &E0));
  alpha = std::min<PetscReal>(1.0, alpha);
  const PetscReal alpha_ccd = alpha;
  ctx->min_alpha_ccd = std::min<double>(ctx->min_alpha_ccd, alpha);

  const double roundoff = 1e-12 * std::max(1.0, std::abs(E0));
  bool accepted = false;
  PetscReal E = E0;
  int invalid_trials = 0;  // halvings forced by an inverted element (the rest: by the energy)
  for (int halvings = 0; halvings < 60 && alpha > 0; ++halvings, alpha *= 0.5) {
    PetscBool valid;
    PetscCall(ctx->potential->segment_is_valid(alpha, &valid));
    if (!valid) {
      ++invalid_trials;
      continue;
    }
    PetscCall(ctx->potential->segment_objective(alpha, &E));
    if (!std::isfinite(E)) continue;
    const bool armijo = E <= E0 + ctx->armijo * alpha * slope;
    const bool unresolvable = std::abs(alpha * slope) < roundoff && E <= E0 + roundoff;
    if (armijo || unresolvable) {
      accepted = true;
      break;
    }
  }
  PetscCall(VecScale(Y, -1.0));
  if (!accepted && ctx->exact_hessian) {
    // No admissible step along the exact Hessian's direction: dropped as a failed solve is.
    ctx->discarded = true;
    count_exact_failure(ctx);
    PetscCall(PetscInfo(snes, "exact contact Hessian: no admissible step; dropped\n"));
    PetscCall(stay_put(ls, Y));
    PetscFunctionReturn(0);
  }
  if (!accepted) {
    PetscCall(PetscInfo(snes, "IPC line search: no admissible decrease along the Newton direction\n"));
    PetscCall(SNESLineSearchSetReason(ls, SNES_LINESEARCH_FAILED_REDUCT));
    PetscFunctionReturn(0);
  }
  if (ctx->exact_hessian && alpha < alpha_ccd) {
    // The exact Hessian is taken on the premise that Newton is where its full steps hold; a
    // step the line search had to cut says it is not (a fast impact's compressed elements
    // otherwise took such directions until the line search stalled). The step stands, and the
    // next iterations project (newton_solver.hpp).
    count_exact_failure(ctx);
    PetscCall(PetscInfo(snes, "exact contact Hessian: step cut to %g of %g; projecting next\n", (double)alpha,
                        (double)alpha_ccd));
  }
  ctx->min_alpha = std::min<double>(ctx->min_alpha, alpha);
  ctx->small_steps_in_a_row = alpha < ctx->alpha_floor ? ctx->small_steps_in_a_row + 1 : 0;
  ctx->last_alpha = alpha;
  ctx->last_alpha_ccd = alpha_ccd;
  ctx->last_invalid_trials = invalid_trials;
  PetscCall(PetscInfo(snes, "IPC line search: alpha %g (collision-free bound %g), E %.12g -> %.12g, |p|_inf %g\n",
                      (double)alpha, (double)alpha_ccd, (double)E0, (double)E, (double)ctx->direction_inf_norm));
  // The accepted trial state X + αp, p = −Y, bit for bit as segment_objective built it.
  PetscCall(VecWAXPY(W, -alpha, Y, X));
  PetscCall(VecCopy(W, X));
  PetscCall(SNESComputeFunction(snes, X, F));
  PetscCall(VecScale(Y, alpha));  // Y := the step actually taken, for PETSc's step norms
  PetscCall(SNESLineSearchSetLambda(ls, alpha));
  PetscCall(SNESLineSearchComputeNorms(ls));
  PetscFunctionReturn(0);
}

// Only dipc's criterion ends a solve as converged (newton_solver.hpp); PETSc's tests are
// consulted first only when the user gave one of them. ctx->ended_by names the deciding test.
PetscErrorCode velocity_convergence_test(SNES snes, PetscInt it, PetscReal xnorm, PetscReal snorm, PetscReal fnorm,
                                         SNESConvergedReason* reason, void* ctx_) {
  auto* ctx = static_cast<NewtonSolver::LineSearchContext*>(ctx_);
  PetscFunctionBeginUser;
  *reason = SNES_CONVERGED_ITERATING;
  // A stop request first: SNES calls this test on every rank once before the first Newton
  // iteration and after each line search, so a collective check here costs one small
  // reduction per iteration and bounds the wait for a stop by one iteration, however many a
  // step takes (issue 32).
  if (ctx->stop_requested && ctx->stop_requested()) {
    *reason = kStopRequestedReason;
    ctx->stopped = true;
    ctx->ended_by = "stop requested";
    PetscFunctionReturn(0);
  }
  // A discarded direction (ipc_line_search) moved nothing: no test may read its zero step.
  if (ctx->petsc_tests && !ctx->discarded) {
    PetscCall(SNESConvergedDefault(snes, it, xnorm, snorm, fnorm, reason, nullptr));
    if (*reason != SNES_CONVERGED_ITERATING) {
      ctx->ended_by = std::string(*reason > 0 ? "PETSc test (user -snes_ option): " : "") +
                      SNESConvergedReasons[*reason];
      PetscFunctionReturn(0);
    }
  }
  PetscReal atol, rtol, stol;
  PetscInt max_it, max_funcs, funcs;
  PetscCall(SNESGetTolerances(snes, &atol, &rtol, &stol, &max_it, &max_funcs));
  PetscCall(SNESGetNumberFunctionEvals(snes, &funcs));
  const double velocity = ctx->direction_inf_norm / ctx->step_length;
  if (!std::isfinite(fnorm)) {
    *reason = SNES_DIVERGED_FNORM_NAN;
    ctx->ended_by = "gradient is not finite";
  } else if (it == 0 && fnorm == 0) {
    *reason = SNES_CONVERGED_FNORM_ABS;  // the start is the minimiser: nothing moves
    ctx->ended_by = "zero gradient";
  } else if (it > 0 && !ctx->discarded && velocity < ctx->velocity_tol) {
    PetscCall(PetscInfo(snes, "Converged: |p|_inf / h = %g < %g\n", velocity, ctx->velocity_tol));
    *reason = SNES_CONVERGED_SNORM_RELATIVE;
    ctx->ended_by = "velocity";
  } else if (ctx->small_steps_in_a_row >= kStallIterations) {
    *reason = SNES_DIVERGED_LINE_SEARCH;
    // What held α down: the collision-free bound (contact), trial states with an inverted
    // element, or the energy (Armijo).
    char text[256];
    std::snprintf(
        text, sizeof text,
        "line search stalled (alpha < %g in %d Newton iterations in a row; last alpha %.2g of a collision-free "
        "bound %.2g, %d of its halvings for an inverted element; |p|_inf/h %.3g)",
        ctx->alpha_floor, kStallIterations, ctx->last_alpha, ctx->last_alpha_ccd, ctx->last_invalid_trials, velocity);
    ctx->ended_by = text;
  } else if (it >= max_it) {
    *reason = SNES_DIVERGED_MAX_IT;
    char text[160];
    std::snprintf(text, sizeof text, "no convergence in %d Newton iterations (|p|_inf/h %.3g, tolerance %.3g)",
                  static_cast<int>(max_it), velocity, ctx->velocity_tol);
    ctx->ended_by = text;
  } else if (max_funcs >= 0 && funcs >= max_funcs) {
    *reason = SNES_DIVERGED_FUNCTION_COUNT;
    ctx->ended_by = "-snes_max_funcs reached";
  }
  PetscFunctionReturn(0);
}

}  // namespace dipc
