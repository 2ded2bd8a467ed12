// PETSc log stages of a dipc run, so that -log_view breaks the time down by phase.
// Registered on first use; every rank must call log_stages() in the same order.
#pragma once
#include <petscsys.h>

namespace dipc {

struct LogStages {
  PetscLogStage partition, setup, solve, assembly, output;
};
const LogStages& log_stages();

// Pushes a stage for the lifetime of the object.
class StageScope {
 public:
  explicit StageScope(PetscLogStage stage) { PetscLogStagePush(stage); }
  ~StageScope() { PetscLogStagePop(); }
  StageScope(const StageScope&) = delete;
  StageScope& operator=(const StageScope&) = delete;
};

}  // namespace dipc
