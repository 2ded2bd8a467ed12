#include "nonlinear/step_recovery.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "math/number_text.hpp"

namespace dipc {

namespace {

// Sums the work of `sub` into `total` and takes its end state.
void accumulate(const StepReport& sub, StepReport* total) {
  NewtonReport& n = total->newton;
  n.iterations += sub.newton.iterations;
  n.linear_iterations += sub.newton.linear_iterations;
  n.preconditioner_rebuilds += sub.newton.preconditioner_rebuilds;
  n.exact_hessian_iterations += sub.newton.exact_hessian_iterations;
  n.exact_hessian_fallbacks += sub.newton.exact_hessian_fallbacks;
  n.min_alpha = std::min(n.min_alpha, sub.newton.min_alpha);
  n.min_alpha_ccd = std::min(n.min_alpha_ccd, sub.newton.min_alpha_ccd);
  total->alpha_ccd = std::min(total->alpha_ccd, sub.alpha_ccd);
  total->dirichlet_substeps += sub.dirichlet_substeps;
  total->linear_solve_seconds += sub.linear_solve_seconds;
  total->broad_phase_seconds += sub.broad_phase_seconds;
  total->ccd_seconds += sub.ccd_seconds;
  total->barrier_seconds += sub.barrier_seconds;
  total->exchange_seconds += sub.exchange_seconds;
  if (!sub.failure.empty()) return;
  n.step_inf_norm = sub.newton.step_inf_norm;
  n.reason = sub.newton.reason;
  n.ended_by = sub.newton.ended_by;
  total->time = sub.time;
  total->dt = std::min(total->dt, sub.dt);
  total->energy = sub.energy;
  total->min_volume_ratio = sub.min_volume_ratio;
  total->contact_pairs = sub.contact_pairs;
  total->contact_pairs_by_kind = sub.contact_pairs_by_kind;
  total->min_distance = sub.min_distance;
  total->kappa = sub.kappa;
}

// Times and steps in messages, with %g: std::to_string's fixed 6 decimals print small steps as 0.000000.
}  // namespace

StepRecovery::StepRecovery(TimeIntegrator& integrator, double dt_min)
    : integrator_(integrator), dt_(integrator.scene_dt()), dt_min_(dt_min) {
  if (!(dt_min > 0) || dt_min > dt_)
    throw std::invalid_argument("the smallest step must be in (0, dt = " + format_number(dt_) + "]");
}

PetscErrorCode StepRecovery::step(StepReport* report,
                                  const std::function<PetscErrorCode(const StepReport&)>& on_substep) {
  PetscFunctionBeginUser;
  const double start = MPI_Wtime();
  *report = StepReport{};
  report->step = steps_taken_ + 1;
  report->dt = dt_;
  report->substeps = 0;
  // Position within the step: `done` sub-steps of dt/2^level_ taken. The end of sub-step j is
  // (k·2^L + j)·(dt/2^L): an exact integer times an exact power-of-two scaling of dt.
  const double k = steps_taken_;
  PetscCall(step_start_.save(integrator_));
  const State recovery_start = state();
  // Once an attempt failed, the step's retries solve conservatively (NewtonSolver::set_retrying:
  // the projected contact Hessian, a tighter CG); the next scene step starts as usual.
  PetscCall(integrator_.set_retrying(false));
  long done = 0;
  for (;;) {
    const double scale = std::ldexp(1.0, level_);
    if (done == static_cast<long>(scale)) break;
    const double t_end = (k * scale + static_cast<double>(done + 1)) * std::ldexp(dt_, -level_);
    StepReport sub;
    PetscCall(integrator_.advance(t_end, &sub));
    accumulate(sub, report);
    if (sub.stopped) {
      PetscCall(step_start_.restore(integrator_));
      resume(recovery_start);
      report->stopped = true;
      break;
    }
    if (sub.failure.empty()) {
      ++report->substeps;
      ++done;
      ++successes_at_level_;
      // Grow back once two sub-steps in a row succeeded and the position lies on the coarser grid.
      if (level_ > 0 && successes_at_level_ >= 2 && done % 2 == 0) {
        --level_;
        done /= 2;
        successes_at_level_ = 0;
      }
      if (on_substep && done < static_cast<long>(std::ldexp(1.0, level_))) PetscCall(on_substep(sub));
      continue;
    }
    const double h = std::ldexp(dt_, -level_);
    char line[512];
    std::snprintf(line, sizeof line, "t %.10g, dt %.4g: %s", integrator_.time(), h, sub.failure.c_str());
    report->cuts.emplace_back(line);
    if (sub.fatal || 0.5 * h < dt_min_ || level_ >= 60) {
      report->fatal = sub.fatal;
      report->failure = sub.fatal
                            ? sub.failure
                            : "at t = " + format_number(integrator_.time()) + " with dt = " + format_number(h) + ": " +
                                  sub.failure + "; step recovery ran out (halving would go below -dipc_dt_min " +
                                  format_number(dt_min_) + ")";
      break;
    }
    ++report->dt_cuts;
    PetscCall(integrator_.set_retrying(true));
    ++level_;
    done *= 2;
    successes_at_level_ = 0;
  }
  report->wall_seconds = MPI_Wtime() - start;
  if (report->failure.empty() && !report->stopped) ++steps_taken_;
  PetscFunctionReturn(0);
}

}  // namespace dipc
