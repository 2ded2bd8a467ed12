// StepSnapshot: a TimeIntegrator's state at the start of a scene step, kept so that a step a
// stop request abandons part-way (issue 32) can be undone: by then step recovery may have
// accepted sub-steps of it, and each attempt overwrote the previous positions, the friction lag
// and the step length, so the state of the last completed step, which the checkpoint must hold,
// exists nowhere else. It is what a checkpoint stores (checkpoint.hpp): positions, velocities,
// previous positions, friction's lag positions and the ResumeState scalars. Saving costs four
// vector copies per scene step (no communication), and four vectors of memory.
#pragma once
#include <petscvec.h>

#include "nonlinear/time_integrator.hpp"

namespace dipc {

class StepSnapshot {
 public:
  StepSnapshot() = default;
  ~StepSnapshot();
  StepSnapshot(const StepSnapshot&) = delete;
  StepSnapshot& operator=(const StepSnapshot&) = delete;

  // Local: copies the integrator's state (the vectors are made on the first call).
  PetscErrorCode save(const TimeIntegrator& integrator);
  // Collective (TimeIntegrator::resume re-freezes friction's pairs): puts the saved state back.
  PetscErrorCode restore(TimeIntegrator& integrator) const;

 private:
  Vec x_ = nullptr, v_ = nullptr, x_n_ = nullptr, x_lag_ = nullptr;  // x_lag_: friction runs only
  TimeIntegrator::ResumeState scalars_;
};

}  // namespace dipc
