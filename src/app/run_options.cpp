#include "app/run_options.hpp"

#include <cstdio>

namespace dipc {

PetscErrorCode read_run_options(MPI_Comm comm, RunOptions* o) {
  PetscFunctionBeginUser;
  char dir[PETSC_MAX_PATH_LEN] = "";
  PetscBool set = PETSC_FALSE, no_output = PETSC_FALSE, quiet = PETSC_FALSE;
  PetscInt steps = o->steps, refine = o->refine;
  PetscOptionsBegin(comm, nullptr, "dipc run options", "dipc");
  PetscCall(PetscOptionsReal("-dipc_velocity_tol",
                             "Newton tolerance on |p|_inf/h (length/s); default: velocity_tol_rel x bounding-box diagonal",
                             "", o->velocity_tol, &o->velocity_tol, nullptr));
  PetscCall(PetscOptionsReal("-dipc_velocity_tol_rel", "Newton tolerance relative to the bounding-box diagonal (1/s)", "",
                             o->velocity_tol_rel, &o->velocity_tol_rel, nullptr));
  PetscCall(PetscOptionsInt("-dipc_steps", "Number of time steps (overrides the scene's time.steps)", "", steps, &steps, nullptr));
  PetscCall(PetscOptionsInt("-dipc_refine", "Multiply the resolution of every generated box by this factor", "", refine,
                            &refine, nullptr));
  PetscCall(PetscOptionsString("-dipc_output", "Output directory (overrides the scene's output.directory)", "", dir, dir,
                               sizeof(dir), &set));
  PetscCall(PetscOptionsBool("-dipc_no_output", "Write no HDF5/XDMF/CSV output", "", no_output, &no_output, nullptr));
  PetscCall(PetscOptionsBool("-dipc_quiet", "Do not print one line per time step", "", quiet, &quiet, nullptr));
  PetscBool setup_only = o->setup_only ? PETSC_TRUE : PETSC_FALSE;
  PetscCall(PetscOptionsBool("-dipc_setup_only",
                             "Build the mesh, partition and solver setup, report them and take no step (setup benchmarks)",
                             "", setup_only, &setup_only, nullptr));
  o->setup_only = setup_only;
  PetscBool check = o->check_invariants ? PETSC_TRUE : PETSC_FALSE;
  PetscCall(PetscOptionsBool("-dipc_check_invariants",
                             "After every step verify det J > 0, no edge-triangle intersection and d_min > 0", "", check,
                             &check, nullptr));
  o->check_invariants = check;
  char backend[16];
  std::snprintf(backend, sizeof backend, "%s", o->backend.c_str());
  PetscCall(PetscOptionsString("-dipc_backend", "Where elements and contact are evaluated: cpu, cuda or auto", "", backend,
                               backend, sizeof(backend), nullptr));
  o->backend = backend;
  char partitioner[16];
  std::snprintf(partitioner, sizeof partitioner, "%s", o->partitioner.c_str());
  PetscCall(PetscOptionsString("-dipc_partitioner",
                               "Element partitioner: metis (on rank 0), ptscotch (parallel) or auto (metis up to "
                               "-dipc_metis_max_elements elements, ptscotch above)",
                               "", partitioner, partitioner, sizeof(partitioner), nullptr));
  o->partitioner = partitioner;
  PetscInt metis_max = static_cast<PetscInt>(o->metis_max_elements);
  PetscCall(PetscOptionsInt("-dipc_metis_max_elements",
                            "Largest mesh (elements) that -dipc_partitioner auto partitions with METIS on rank 0", "",
                            metis_max, &metis_max, nullptr));
  o->metis_max_elements = metis_max;
  PetscInt crossover = static_cast<PetscInt>(o->auto_gpu_min_elements);
  PetscCall(PetscOptionsInt("-dipc_auto_gpu_elements", "Elements per rank from which -dipc_backend auto uses the GPU", "",
                            crossover, &crossover, nullptr));
  o->auto_gpu_min_elements = crossover;
  PetscCall(PetscOptionsReal("-dipc_dt_min",
                             "Shortest sub-step of step recovery: a failed step is retried with dt halved down to this "
                             "(default: the scene's dt / 1024)",
                             "", o->dt_min, &o->dt_min, nullptr));
  PetscCall(PetscOptionsReal("-dipc_alpha_floor",
                             "A Newton solve has stalled (and the step fails) when the line-search step stays below this "
                             "in 5 iterations in a row",
                             "", o->alpha_floor, &o->alpha_floor, nullptr));
  PetscBool substeps = o->output_substeps ? PETSC_TRUE : PETSC_FALSE;
  PetscCall(PetscOptionsBool("-dipc_output_substeps", "Also write the sub-steps of steps that recovery cut", "", substeps,
                             &substeps, nullptr));
  o->output_substeps = substeps;
  PetscInt every = o->checkpoint_every;
  PetscCall(PetscOptionsInt("-dipc_checkpoint_every",
                            "Write a checkpoint every N steps into the output directory (the newest two are kept)", "",
                            every, &every, nullptr));
  o->checkpoint_every = static_cast<int>(every);
  PetscCall(PetscOptionsReal("-dipc_checkpoint_minutes",
                             "Write a checkpoint at the first step boundary after M wall-clock minutes since the last "
                             "(rank 0's clock)",
                             "", o->checkpoint_minutes, &o->checkpoint_minutes, nullptr));
  char restart[PETSC_MAX_PATH_LEN] = "";
  PetscBool restart_set = PETSC_FALSE;
  PetscCall(PetscOptionsString("-dipc_restart",
                               "Continue from a checkpoint: a file, or auto (the newest in the output directory; "
                               "none there: start from step 0)",
                               "", restart, restart, sizeof(restart), &restart_set));
  if (restart_set) o->restart = restart;
  PetscOptionsEnd();
  o->steps = static_cast<int>(steps);
  o->refine = static_cast<int>(refine);
  if (set) o->output_dir = dir;
  o->write_output = !no_output;
  o->quiet = quiet;
  PetscFunctionReturn(0);
}

}  // namespace dipc
