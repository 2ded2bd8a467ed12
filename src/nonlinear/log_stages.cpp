#include "nonlinear/log_stages.hpp"

namespace dipc {

const LogStages& log_stages() {
  static LogStages s = [] {
    LogStages r{};
    PetscLogStageRegister("dipc: partition", &r.partition);
    PetscLogStageRegister("dipc: setup", &r.setup);
    PetscLogStageRegister("dipc: solve", &r.solve);
    PetscLogStageRegister("dipc: assembly", &r.assembly);
    PetscLogStageRegister("dipc: output", &r.output);
    return r;
  }();
  return s;
}

}  // namespace dipc
