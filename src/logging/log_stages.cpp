#include "logging/log_stages.hpp"

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

const LogEvents& log_events() {
  static LogEvents e = [] {
    LogEvents r{};
    PetscClassId id;
    PetscClassIdRegister("dipc", &id);
    PetscLogEventRegister("dipcEnergy", id, &r.energy);
    PetscLogEventRegister("dipcGradient", id, &r.gradient);
    PetscLogEventRegister("dipcHessian", id, &r.hessian);
    PetscLogEventRegister("dipcValidity", id, &r.validity);
    PetscLogEventRegister("dipcCooReduction", id, &r.coo_reduction);
    PetscLogEventRegister("dipcNodeBlocks", id, &r.node_blocks);
    PetscLogEventRegister("dipcPatternRemap", id, &r.pattern_remap);
    PetscLogEventRegister("dipcDirectMatrix", id, &r.direct_matrix);
    PetscLogEventRegister("dipcMatrixRows", id, &r.matrix_rows);
    PetscLogEventRegister("dipcMatrixMake", id, &r.matrix_make);
    PetscLogEventRegister("dipcPatternGroups", id, &r.pattern_groups);
    PetscLogEventRegister("dipcPatternReserve", id, &r.pattern_reserve);
    PetscLogEventRegister("dipcPatternMap", id, &r.pattern_map);
    PetscLogEventRegister("dipcPatternDevice", id, &r.pattern_device);
    PetscLogEventRegister("dipcSetupElements", id, &r.setup_elements);
    PetscLogEventRegister("dipcSetupMasses", id, &r.setup_masses);
    PetscLogEventRegister("dipcSetupForms", id, &r.setup_forms);
    PetscLogEventRegister("dipcSetupState", id, &r.setup_state);
    PetscLogEventRegister("dipcSetupSolver", id, &r.setup_solver);
    PetscLogEventRegister("dipcContactCheck", id, &r.contact_check);
    PetscLogEventRegister("dipcGhostSurfaces", id, &r.ghost_surfaces);
    PetscLogEventRegister("dipcBroadPhase", id, &r.broad_phase);
    PetscLogEventRegister("dipcPairLists", id, &r.pair_lists);
    PetscLogEventRegister("dipcActiveSet", id, &r.active_set);
    PetscLogEventRegister("dipcCCD", id, &r.ccd);
    PetscLogEventRegister("dipcFrictionLag", id, &r.friction_lag);
    PetscLogEventRegister("dipcFriction", id, &r.friction);
    PetscLogEventRegister("dipcNewtonUpdate", id, &r.newton_update);
    PetscLogEventRegister("dipcLineSearch", id, &r.line_search);
    return r;
  }();
  return e;
}

}  // namespace dipc
