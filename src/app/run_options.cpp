#include "app/run_options.hpp"

#include <cstdio>
#include <cstring>

#include "options/dipc_options.hpp"

namespace dipc {

namespace {

// The rows of options/dipc_options.hpp: names, help texts, the manual section that -help prints
// in parentheses after the help text (as PETSc prints the manual page of the function that an
// option sets; ours names the struct that holds the setting) and the choices, in the order of
// PetscOptionsEList's index.
constexpr const OptionSpec& kVelocityTol = dipc_option("-dipc_velocity_tol");
constexpr const OptionSpec& kVelocityTolRel = dipc_option("-dipc_velocity_tol_rel");
constexpr const OptionSpec& kSteps = dipc_option("-dipc_steps");
constexpr const OptionSpec& kRefine = dipc_option("-dipc_refine");
constexpr const OptionSpec& kOutput = dipc_option("-dipc_output");
constexpr const OptionSpec& kNoOutput = dipc_option("-dipc_no_output");
constexpr const OptionSpec& kQuiet = dipc_option("-dipc_quiet");
constexpr const OptionSpec& kCheckInvariants = dipc_option("-dipc_check_invariants");
constexpr const OptionSpec& kBackend = dipc_option("-dipc_backend");
constexpr const OptionSpec& kAutoGpuElements = dipc_option("-dipc_auto_gpu_elements");
constexpr const OptionSpec& kPartitioner = dipc_option("-dipc_partitioner");
constexpr const OptionSpec& kMetisMaxElements = dipc_option("-dipc_metis_max_elements");
constexpr const OptionSpec& kHostThreads = dipc_option("-dipc_host_threads");
constexpr const OptionSpec& kSetupOnly = dipc_option("-dipc_setup_only");
constexpr const OptionSpec& kDtMin = dipc_option("-dipc_dt_min");
constexpr const OptionSpec& kAlphaFloor = dipc_option("-dipc_alpha_floor");
constexpr const OptionSpec& kOutputSubsteps = dipc_option("-dipc_output_substeps");
constexpr const OptionSpec& kCheckpointEvery = dipc_option("-dipc_checkpoint_every");
constexpr const OptionSpec& kCheckpointMinutes = dipc_option("-dipc_checkpoint_minutes");
constexpr const OptionSpec& kRestart = dipc_option("-dipc_restart");

// The index of `value` among the choices of `spec`, or `fallback`.
PetscInt choice_index(const OptionSpec& spec, const std::string& value, PetscInt fallback) {
  for (PetscInt i = 0; i < spec.choices.count; ++i)
    if (value == spec.choices.words[i]) return i;
  return fallback;
}

}  // namespace

PetscErrorCode read_run_options(MPI_Comm comm, const Scene& scene, RunOptions* o) {
  PetscFunctionBeginUser;
  // Options whose default is the scene's show the scene's value, so -help lists what a run
  // without them does.
  PetscInt steps = o->steps > 0 ? o->steps : scene.steps, refine = o->refine;
  char dir[PETSC_MAX_PATH_LEN];
  std::snprintf(dir, sizeof dir, "%s", (o->output_dir.empty() ? scene.output_directory : o->output_dir).c_str());
  PetscReal dt_min = o->dt_min > 0 ? o->dt_min : scene.dt / 1024;
  PetscBool no_output = o->write_output ? PETSC_FALSE : PETSC_TRUE, quiet = o->quiet ? PETSC_TRUE : PETSC_FALSE;
  PetscBool setup_only = o->setup_only ? PETSC_TRUE : PETSC_FALSE;
  // A value that is none of the choices (a RunOptions made in code) reads as auto, the last.
  PetscInt partitioner = choice_index(kPartitioner, o->partitioner, kPartitioner.choices.count - 1);
  PetscInt metis_max = static_cast<PetscInt>(o->metis_max_elements), host_threads = o->host_threads;
  PetscBool check = o->check_invariants ? PETSC_TRUE : PETSC_FALSE;
  PetscBool substeps = o->output_substeps ? PETSC_TRUE : PETSC_FALSE;
  PetscInt backend = choice_index(  // the same: auto
      kBackend, o->backend, kBackend.choices.count - 1);
  PetscInt crossover = static_cast<PetscInt>(o->auto_gpu_min_elements), every = o->checkpoint_every;
  char restart[PETSC_MAX_PATH_LEN];
  std::snprintf(restart, sizeof restart, "%s", o->restart.empty() ? "none" : o->restart.c_str());

  PetscOptionsBegin(comm, nullptr, "dipc run options", "dipc");
  PetscCall(PetscOptionsReal(kVelocityTolRel.name, kVelocityTolRel.help, kVelocityTolRel.manual, o->velocity_tol_rel,
                             &o->velocity_tol_rel, nullptr));
  PetscCall(PetscOptionsInt(kSteps.name, kSteps.help, kSteps.manual, steps, &steps, nullptr));
  PetscCall(PetscOptionsInt(kRefine.name, kRefine.help, kRefine.manual, refine, &refine, nullptr));
  PetscCall(PetscOptionsString(kOutput.name, kOutput.help, kOutput.manual, dir, dir, sizeof(dir), nullptr));
  PetscCall(PetscOptionsBool(kNoOutput.name, kNoOutput.help, kNoOutput.manual, no_output, &no_output, nullptr));
  PetscCall(PetscOptionsBool(kQuiet.name, kQuiet.help, kQuiet.manual, quiet, &quiet, nullptr));
  PetscCall(
      PetscOptionsBool(kCheckInvariants.name, kCheckInvariants.help, kCheckInvariants.manual, check, &check, nullptr));
  PetscCall(PetscOptionsEList(kBackend.name, kBackend.help, kBackend.manual, kBackend.choices.words,
                              kBackend.choices.count, kBackend.choices.words[backend], &backend, nullptr));
  PetscCall(PetscOptionsInt(kAutoGpuElements.name, kAutoGpuElements.help, kAutoGpuElements.manual, crossover,
                            &crossover, nullptr));
  PetscCall(PetscOptionsEList(kPartitioner.name, kPartitioner.help, kPartitioner.manual, kPartitioner.choices.words,
                              kPartitioner.choices.count, kPartitioner.choices.words[partitioner], &partitioner,
                              nullptr));
  PetscCall(PetscOptionsInt(kMetisMaxElements.name, kMetisMaxElements.help, kMetisMaxElements.manual, metis_max,
                            &metis_max, nullptr));
  PetscCall(
      PetscOptionsInt(kHostThreads.name, kHostThreads.help, kHostThreads.manual, host_threads, &host_threads, nullptr));
  PetscCall(PetscOptionsBool(kSetupOnly.name, kSetupOnly.help, kSetupOnly.manual, setup_only, &setup_only, nullptr));
  PetscCall(PetscOptionsReal(kDtMin.name, kDtMin.help, kDtMin.manual, dt_min, &dt_min, nullptr));
  PetscCall(PetscOptionsReal(kAlphaFloor.name, kAlphaFloor.help, kAlphaFloor.manual, o->alpha_floor, &o->alpha_floor,
                             nullptr));
  PetscCall(PetscOptionsBool(kOutputSubsteps.name, kOutputSubsteps.help, kOutputSubsteps.manual, substeps, &substeps,
                             nullptr));
  PetscCall(
      PetscOptionsInt(kCheckpointEvery.name, kCheckpointEvery.help, kCheckpointEvery.manual, every, &every, nullptr));
  PetscCall(PetscOptionsReal(kCheckpointMinutes.name, kCheckpointMinutes.help, kCheckpointMinutes.manual,
                             o->checkpoint_minutes, &o->checkpoint_minutes, nullptr));
  PetscCall(
      PetscOptionsString(kRestart.name, kRestart.help, kRestart.manual, restart, restart, sizeof(restart), nullptr));
  PetscOptionsEnd();

  o->steps = static_cast<int>(steps);
  o->refine = static_cast<int>(refine);
  o->output_dir = dir;
  o->write_output = !no_output;
  o->quiet = quiet;
  o->check_invariants = check;
  o->backend = kBackend.choices.words[backend];
  o->auto_gpu_min_elements = crossover;
  o->partitioner = kPartitioner.choices.words[partitioner];
  o->metis_max_elements = metis_max;
  o->host_threads = static_cast<int>(host_threads);
  o->setup_only = setup_only;
  o->dt_min = dt_min;
  o->output_substeps = substeps;
  o->checkpoint_every = static_cast<int>(every);
  o->restart = std::strcmp(restart, "none") == 0 ? "" : restart;
  PetscFunctionReturn(0);
}

PetscErrorCode read_velocity_tol(MPI_Comm comm, const RunOptions& o, double diagonal, double* velocity_tol) {
  PetscFunctionBeginUser;
  PetscReal tol = o.velocity_tol > 0 ? o.velocity_tol : o.velocity_tol_rel * diagonal;
  PetscOptionsBegin(comm, nullptr, "dipc Newton tolerance", "dipc");
  PetscCall(PetscOptionsReal(kVelocityTol.name, kVelocityTol.help, kVelocityTol.manual, tol, &tol, nullptr));
  PetscOptionsEnd();
  *velocity_tol = tol;
  PetscFunctionReturn(0);
}

}  // namespace dipc
