// StepSnapshot (see step_snapshot.hpp).
#include "nonlinear/step_snapshot.hpp"

#include <utility>

namespace dipc {

StepSnapshot::~StepSnapshot() {
  // A destructor cannot return the error: a failing destroy (a defect) aborts.
  for (Vec* v : {&x_, &v_, &x_n_, &x_lag_}) PetscCallAbort(PETSC_COMM_SELF, VecDestroy(v));
}

PetscErrorCode StepSnapshot::save(const TimeIntegrator& integrator) {
  PetscFunctionBeginUser;
  const std::pair<Vec*, Vec> fields[] = {{&x_, integrator.positions()},
                                         {&v_, integrator.velocities()},
                                         {&x_n_, integrator.previous_positions()},
                                         {&x_lag_, integrator.friction_lag_positions()}};
  for (const auto& [copy, from] : fields) {
    if (!from) continue;  // no friction: no lag positions
    if (!*copy) PetscCall(VecDuplicate(from, copy));
    PetscCall(VecCopy(from, *copy));
  }
  scalars_ = integrator.resume_state();
  PetscFunctionReturn(0);
}

PetscErrorCode StepSnapshot::restore(TimeIntegrator& integrator) const {
  PetscFunctionBeginUser;
  PetscCheck(x_, PETSC_COMM_SELF, PETSC_ERR_ARG_WRONGSTATE, "StepSnapshot::restore before save");
  const std::pair<Vec, Vec> fields[] = {{x_, integrator.positions()},
                                        {v_, integrator.velocities()},
                                        {x_n_, integrator.previous_positions()},
                                        {x_lag_, integrator.friction_lag_positions()}};
  for (const auto& [copy, to] : fields)
    if (copy && to) PetscCall(VecCopy(copy, to));
  // After the vectors: with friction it freezes the pairs again at the restored lag positions.
  PetscCall(integrator.resume(scalars_));
  PetscFunctionReturn(0);
}

}  // namespace dipc
