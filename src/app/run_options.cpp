#include "app/run_options.hpp"

#include <cstdio>
#include <cstring>

namespace dipc {

namespace {

// The third argument of PetscOptions*: -help prints it in parentheses after the help text, as
// PETSc prints the manual page of the function that an option sets. Ours names the struct that
// holds the setting (app/run_options.hpp).
constexpr const char* kManual = "RunOptions";

// The backends, in the order of PetscOptionsEList's index.
constexpr const char* kBackends[] = {"cpu", "cuda", "auto"};

// The partitioners, in the order of PetscOptionsEList's index (partition/slice_partition.hpp).
constexpr const char* kPartitioners[] = {"metis", "ptscotch", "rcb", "auto"};

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
  PetscInt partitioner = 3, metis_max = static_cast<PetscInt>(o->metis_max_elements), host_threads = o->host_threads;
  for (PetscInt i = 0; i < 4; ++i)
    if (o->partitioner == kPartitioners[i]) partitioner = i;
  PetscBool check = o->check_invariants ? PETSC_TRUE : PETSC_FALSE;
  PetscBool substeps = o->output_substeps ? PETSC_TRUE : PETSC_FALSE;
  PetscInt backend = 2, crossover = static_cast<PetscInt>(o->auto_gpu_min_elements), every = o->checkpoint_every;
  for (PetscInt i = 0; i < 3; ++i)
    if (o->backend == kBackends[i]) backend = i;
  char restart[PETSC_MAX_PATH_LEN];
  std::snprintf(restart, sizeof restart, "%s", o->restart.empty() ? "none" : o->restart.c_str());

  PetscOptionsBegin(comm, nullptr, "dipc run options", "dipc");
  PetscCall(PetscOptionsReal("-dipc_velocity_tol_rel",
                             "Newton tolerance relative to the bounding-box diagonal (1/s): -dipc_velocity_tol is this "
                             "times the diagonal unless given",
                             kManual, o->velocity_tol_rel, &o->velocity_tol_rel, nullptr));
  PetscCall(PetscOptionsInt("-dipc_steps", "Number of time steps (default: the scene's time.steps)", kManual, steps, &steps,
                            nullptr));
  PetscCall(PetscOptionsInt("-dipc_refine", "Multiply the resolution of every generated box by this factor", kManual,
                            refine, &refine, nullptr));
  PetscCall(PetscOptionsString("-dipc_output", "Output directory (default: the scene's output.directory)", kManual, dir,
                               dir, sizeof(dir), nullptr));
  PetscCall(PetscOptionsBool("-dipc_no_output", "Write no HDF5/XDMF/CSV output", kManual, no_output, &no_output, nullptr));
  PetscCall(PetscOptionsBool("-dipc_quiet", "Do not print one line per time step", kManual, quiet, &quiet, nullptr));
  PetscCall(PetscOptionsBool("-dipc_check_invariants",
                             "After every step verify det J > 0, no edge-triangle intersection and d_min > 0", kManual,
                             check, &check, nullptr));
  PetscCall(PetscOptionsEList("-dipc_backend", "Where elements and contact are evaluated", kManual, kBackends, 3,
                              kBackends[backend], &backend, nullptr));
  PetscCall(PetscOptionsInt("-dipc_auto_gpu_elements", "Elements per rank from which -dipc_backend auto uses the GPU",
                            kManual, crossover, &crossover, nullptr));
  PetscCall(PetscOptionsEList("-dipc_partitioner",
                              "Element partitioner: metis (on rank 0), ptscotch (parallel), rcb (parallel recursive "
                              "coordinate bisection) or auto (metis up to -dipc_metis_max_elements elements, above "
                              "ptscotch where PETSc has it, rcb otherwise)",
                              kManual, kPartitioners, 4, kPartitioners[partitioner], &partitioner, nullptr));
  PetscCall(PetscOptionsInt("-dipc_metis_max_elements",
                            "Largest mesh (elements) that -dipc_partitioner auto partitions with METIS on rank 0", kManual,
                            metis_max, &metis_max, nullptr));
  PetscCall(PetscOptionsInt("-dipc_host_threads",
                            "Threads per rank of the partition's and the setup's host loops (0: the cores this rank may "
                            "run on, shared with the node's other ranks on them)",
                            kManual, host_threads, &host_threads, nullptr));
  PetscCall(PetscOptionsBool("-dipc_setup_only",
                             "Build the mesh, partition and solver setup, report them and take no step (setup benchmarks)",
                             kManual, setup_only, &setup_only, nullptr));
  PetscCall(PetscOptionsReal("-dipc_dt_min",
                             "Shortest sub-step of step recovery: a failed step is retried with dt halved down to this "
                             "(default: the scene's dt / 1024)",
                             kManual, dt_min, &dt_min, nullptr));
  PetscCall(PetscOptionsReal("-dipc_alpha_floor",
                             "A Newton solve has stalled (and the step fails) when the line-search step stays below this "
                             "in 5 iterations in a row",
                             kManual, o->alpha_floor, &o->alpha_floor, nullptr));
  PetscCall(PetscOptionsBool("-dipc_output_substeps", "Also write the sub-steps of steps that recovery cut", kManual,
                             substeps, &substeps, nullptr));
  PetscCall(PetscOptionsInt("-dipc_checkpoint_every",
                            "Write a checkpoint every N steps into the output directory (the newest two are kept; 0: "
                            "not by step count)",
                            kManual, every, &every, nullptr));
  PetscCall(PetscOptionsReal("-dipc_checkpoint_minutes",
                             "Write a checkpoint at the first step boundary after M wall-clock minutes since the last "
                             "(rank 0's clock; 0: not by time)",
                             kManual, o->checkpoint_minutes, &o->checkpoint_minutes, nullptr));
  PetscCall(PetscOptionsString("-dipc_restart",
                               "Continue from a checkpoint: a file, auto (the newest in the output directory; none "
                               "there: start from step 0) or none",
                               kManual, restart, restart, sizeof(restart), nullptr));
  PetscOptionsEnd();

  o->steps = static_cast<int>(steps);
  o->refine = static_cast<int>(refine);
  o->output_dir = dir;
  o->write_output = !no_output;
  o->quiet = quiet;
  o->check_invariants = check;
  o->backend = kBackends[backend];
  o->auto_gpu_min_elements = crossover;
  o->partitioner = kPartitioners[partitioner];
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
  PetscCall(PetscOptionsReal("-dipc_velocity_tol",
                             "Newton tolerance on |p|_inf/h (length/s); default: -dipc_velocity_tol_rel x the scene's "
                             "bounding-box diagonal",
                             kManual, tol, &tol, nullptr));
  PetscOptionsEnd();
  *velocity_tol = tol;
  PetscFunctionReturn(0);
}

}  // namespace dipc
