// PETSc log stages and events of a dipc run, so that -log_view breaks the time down by phase.
// Registered on first use; every rank must call log_stages() and log_events() in the same order.
#pragma once
#include <petscsys.h>

namespace dipc {

struct LogStages {
  PetscLogStage partition, setup, solve, assembly, output;
};
const LogStages& log_stages();

// Events: the potential's evaluations and matrix pattern (IncrementalPotential), one per
// phase of the time integrator's setup (TimeIntegrator::setup), and the contact forms' parts.
struct LogEvents {
  PetscLogEvent energy, gradient, hessian, validity, coo_reduction, node_blocks, direct_matrix, pattern_remap;
  PetscLogEvent matrix_rows, matrix_make;  // direct_matrix's parts: its rows' pattern, the Mat from it
  // The changing part's steps, in coo_reduction and pattern_remap: the terms' node groups, the
  // reserve's blocks (new matrices only), the values' targets among the entries, and the raw
  // arrays and targets sized and sent to the device.
  PetscLogEvent pattern_groups, pattern_reserve, pattern_map, pattern_device;
  PetscLogEvent setup_elements, setup_masses, setup_forms, setup_state, setup_solver, contact_check;
  // The contact and friction forms' parts (ContactForm, FrictionForm): ghost surfaces, broad
  // phase, the device pair lists (built on the host, uploaded), the active-set pass, CCD, the
  // friction lag update and friction's evaluations.
  PetscLogEvent ghost_surfaces, broad_phase, pair_lists, active_set, ccd, friction_lag, friction;
  // The Newton solver's own work around the evaluations (NewtonSolver): the start-of-iteration
  // hook (the forms' updates, the pattern refresh, a new matrix) and the whole line search (CCD
  // bound, trial energies and validity, the accepted state's gradient).
  PetscLogEvent newton_update, line_search;
};
const LogEvents& log_events();

// Pushes a stage for the lifetime of the object.
class StageScope {
 public:
  explicit StageScope(PetscLogStage stage) { PetscLogStagePush(stage); }
  ~StageScope() { PetscLogStagePop(); }
  StageScope(const StageScope&) = delete;
  StageScope& operator=(const StageScope&) = delete;
};

// Logs an event for the lifetime of the object.
class EventScope {
 public:
  explicit EventScope(PetscLogEvent event) : event_(event) { PetscLogEventBegin(event_, 0, 0, 0, 0); }
  ~EventScope() { PetscLogEventEnd(event_, 0, 0, 0, 0); }
  EventScope(const EventScope&) = delete;
  EventScope& operator=(const EventScope&) = delete;

 private:
  PetscLogEvent event_;
};

}  // namespace dipc
