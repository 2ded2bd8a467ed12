// RunOptions: the numerics of a run that live in the PETSc options database (-dipc_*), with
// their defaults and help strings (`dipc -help` lists them). Code that builds a RunOptions
// itself (the tests) may leave the scene-dependent fields at their "the scene's" values
// (steps, dt_min, velocity_tol <= 0; output_dir empty); read_run_options fills them in.
#pragma once
#include <petscsys.h>

#include <string>

#include "app/backend.hpp"
#include "io/scene.hpp"

namespace dipc {

struct RunOptions {
  // Newton stops when ‖p‖∞ / h < velocity_tol (IPC's criterion). Default: relative to the
  // scene's bounding-box diagonal L, velocity_tol = velocity_tol_rel · L per second.
  double velocity_tol = -1;
  double velocity_tol_rel = 1e-5;
  int steps = -1;                 // overrides the scene's number of steps when > 0
  int refine = 1;                 // multiplies every generated box's resolution (scales a scene up)
  std::string output_dir;         // overrides the scene's output directory when set
  bool write_output = true;       // -dipc_no_output: skip HDF5/XDMF/CSV (benchmarks, tests)
  bool quiet = false;             // -dipc_quiet: no per-step lines
  bool report = true;             // run header and timing table (tests and benchmarks turn it off)
  bool check_invariants = false;  // -dipc_check_invariants: verify no inversion/intersection after every step
  bool setup_only = false;        // build everything (so -help lists all options), take no step
  // Step recovery (nonlinear/step_recovery.hpp): the shortest sub-step, ≤ 0 for dt / 1024.
  double dt_min = -1;
  double alpha_floor = 1e-6;     // -dipc_alpha_floor: line-search stall floor (newton_solver.hpp)
  bool output_substeps = false;  // -dipc_output_substeps: also write the sub-steps of cut steps
  std::string preset;            // the -dipc_preset applied (app/solver_presets.hpp); "" for none
  std::string backend = "auto";  // -dipc_backend cpu | cuda | auto (app/backend.hpp)
  long auto_gpu_min_elements = kAutoGpuMinElementsPerRank;  // -dipc_auto_gpu_elements: auto's crossover
  // Checkpoints (app/checkpoint.hpp), in the output directory: every N steps and/or every M
  // wall-clock minutes (0: not by that rule); a stop signal always writes one.
  int checkpoint_every = 0;
  double checkpoint_minutes = 0;
  // Element partitioner (partition/slice_partition.hpp): metis, ptscotch, rcb, or auto = METIS
  // on rank 0 up to metis_max_elements elements; above, PT-Scotch where PETSc has it, RCB otherwise.
  std::string partitioner = "auto";
  long metis_max_elements = 4000000;
  // Threads of the partition's and the setup's host loops (-dipc_host_threads; 0: automatic,
  // app/openmp_threads.hpp: choose_host_threads).
  int host_threads = 0;
  std::string restart;  // -dipc_restart FILE | auto (the newest checkpoint in the output directory); "": none
};

// Reads the -dipc_ run options into *options, whose values are the defaults; those that
// default to the scene's (steps, output directory, dt_min) are shown with the scene's value.
// Values are taken as given: check_option_values (app/option_checks.hpp), which refuses those
// out of range, runs first. Names, help texts and ranges are the rows of options/dipc_options.hpp;
// a new option needs its row there.
PetscErrorCode read_run_options(MPI_Comm comm, const Scene& scene, RunOptions* options);

// The Newton tolerance of the run: -dipc_velocity_tol, whose default (options.velocity_tol when
// set, else velocity_tol_rel x the bounding-box diagonal of the built mesh) is known only once
// the mesh is; run_scene reads it there, so -help shows the real default.
PetscErrorCode read_velocity_tol(MPI_Comm comm, const RunOptions& options, double diagonal, double* velocity_tol);

}  // namespace dipc
