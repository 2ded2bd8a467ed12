// StepRecovery: the scene's steps, each taken in sub-steps when it has to be. A failed attempt
// (Newton limit, failed line search or linear solve, a stalled line search, a prescribed
// motion that cannot be reached) is retried from the start of the sub-step with the step
// halved, down to dt_min; after two successes in a row the step doubles again, towards the
// scene's dt. Sub-steps are dt/2^L, so every sub-step ends on an exact binary fraction of dt
// and every scene step ends exactly at k·dt, whatever cuts were made in between. The retries of
// a scene step solve conservatively (NewtonSolver::set_retrying: the projected contact Hessian in
// every Newton iteration, CG 10 times tighter), until the next scene step.
//
// Every decision follows from collective results (SNES reasons, global reductions), so all
// ranks cut and grow alike.
//
// An attempt that a stop request ended (StepReport::stopped) abandons the whole scene step:
// the integrator and recovery are put back to the step's start (StepSnapshot), the state of
// the last completed step, which a checkpoint then stores (issue 32).
#pragma once
#include <functional>

#include "nonlinear/step_snapshot.hpp"
#include "nonlinear/time_integrator.hpp"

namespace dipc {

class StepRecovery {
 public:
  // dt_min: the shortest sub-step allowed (> 0, ≤ the scene's dt).
  StepRecovery(TimeIntegrator& integrator, double dt_min);

  // Advances from step k = steps_taken() to k + 1 (t = (k+1)·dt). report sums the sub-steps;
  // on_substep (may be empty) sees each accepted sub-step that ends before the scene step does.
  // When recovery runs out, report->failure says at what time, with what step and why, and the
  // state is that of the last accepted sub-step.
  // When a stop request ends an attempt, report->stopped is set, steps_taken() stays and the
  // state is the one before the step.
  PetscErrorCode step(StepReport* report, const std::function<PetscErrorCode(const StepReport&)>& on_substep = {});

  int steps_taken() const { return steps_taken_; }

  // Where recovery stands between scene steps (checkpoints): the sub-step level carries over
  // from one step to the next until two sub-steps in a row succeed.
  struct State {
    int steps_taken = 0, level = 0, successes_at_level = 0;
  };
  State state() const { return {steps_taken_, level_, successes_at_level_}; }
  void resume(const State& s) {
    steps_taken_ = s.steps_taken;
    level_ = s.level;
    successes_at_level_ = s.successes_at_level;
  }

 private:
  TimeIntegrator& integrator_;
  StepSnapshot step_start_;  // the integrator at the start of the scene step in progress
  double dt_, dt_min_;
  int steps_taken_ = 0;
  int level_ = 0;               // sub-steps are dt / 2^level_
  int successes_at_level_ = 0;  // accepted sub-steps in a row at level_
};

}  // namespace dipc
