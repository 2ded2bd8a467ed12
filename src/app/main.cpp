// dipc: distributed IPC for hexahedral solids.
//   mpirun -n N dipc [scene.json] [PETSc and -dipc_ options]
// Without a scene file, runs the default scene embedded in the program.
#include <petscsys.h>

#include <cstdlib>
#include <cstring>
#include <stdexcept>

#include "app/checked_run_options.hpp"
#include "app/options_files.hpp"
#include "app/petsc_input_errors.hpp"
#include "app/simulation.hpp"
#include "app/stop_signals.hpp"

static const char help[] =
    "dipc: implicit neo-Hookean elastodynamics of hexahedral meshes, distributed with MPI + PETSc.\n"
    "Usage: mpirun -n N dipc [scene.json] [options]\n"
    "  scene.json  the scene (JSON); without it, the embedded default scene runs.\n"
    "Numerics are PETSc options: -snes_*, -ksp_*, -pc_*, -log_view, -options_file, and the -dipc_* below.\n\n";

// Rank 0 looks for the -options_file files (where PETSc reads them) before PetscInitialize,
// which would abort the run on a missing one; false, after the message, when one is missing.
static bool options_files_readable(int argc, char** argv) {
  int rank;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  std::string problem;
  if (rank == 0) problem = dipc::options_file_problem({argv + 1, argv + argc}, std::getenv("PETSC_OPTIONS"));
  int missing = !problem.empty();
  MPI_Bcast(&missing, 1, MPI_INT, 0, MPI_COMM_WORLD);
  if (missing && rank == 0) std::fprintf(stderr, "dipc: error: %s\n", problem.c_str());
  return !missing;
}

int main(int argc, char** argv) {
  // The scene file is the first argument unless it is an option; PETSc ignores it.
  const char* scene_path = (argc > 1 && argv[1][0] != '-') ? argv[1] : nullptr;
  // MPI first, so that a missing options file can be reported before PETSc reads the files;
  // PETSc then leaves MPI_Finalize to us.
  MPI_Init(&argc, &argv);
  if (!options_files_readable(argc, argv)) {
    MPI_Finalize();
    return 1;
  }
  PetscCall(PetscInitialize(&argc, &argv, nullptr, help));
  MPI_Comm comm = PETSC_COMM_WORLD;
  dipc::install_stop_signal_handlers();  // after PETSc's, which would abort on SIGTERM
  PetscCall(dipc::push_input_error_handler());

  int status = 0;
  try {
    // The scene before the run options: some of their defaults are the scene's.
    const dipc::Scene scene = scene_path ? dipc::parse_scene_file(scene_path) : dipc::default_scene();
    dipc::RunOptions options;
    PetscCall(dipc::checked_run_options(comm, scene, &options));
    PetscBool help_requested = PETSC_FALSE;
    PetscCall(PetscOptionsHasHelp(nullptr, &help_requested));
    // A PolyFEM scene's keys that dipc ignores or reads its own way, one line each.
    for (const std::string& note : scene.notes) PetscCall(PetscPrintf(comm, "dipc: PolyFEM scene: %s\n", note.c_str()));
    if (help_requested) {
      // The solvers read their options while they are set up, so -help builds everything (and
      // so lists every option with the value this scene would use), then stops: no run
      // header, step or timing table.
      options.setup_only = true;
      options.report = false;
    }
    dipc::RunResult result;
    const PetscErrorCode run_error = dipc::run_scene(scene, comm, options, &result);
    if (run_error == PETSC_ERR_USER_INPUT) throw std::runtime_error(dipc::last_petsc_error_message());
    PetscCall(run_error);
    // Exit status: 1 bad input, 2 a step that step recovery could not take, 3 a violated
    // invariant (an inverted element or an intersection after a step: a solver defect), 4
    // stopped on a signal with a checkpoint written.
    if (!result.failure.empty()) {
      PetscCall(PetscPrintf(comm, "dipc: error: %s\n", result.failure.c_str()));
      status = result.fatal ? 3 : 2;
    }
    // 4: stopped on a signal, with a checkpoint of the last completed step to resume from.
    if (result.stop_signal) {
      PetscCall(PetscPrintf(comm,
                            "dipc: stopped on signal %d after step %d; checkpoint written to %s %.2f s after the "
                            "signal; resume with -dipc_restart auto (same -dipc_output)\n",
                            result.stop_signal, result.steps_taken, result.checkpoint_path.c_str(),
                            result.stop_seconds));
      status = 4;
    }
    if (!result.xdmf_path.empty())
      PetscCall(PetscPrintf(comm, "dipc: %d steps written to %s (open it in ParaView)\n", result.steps_taken,
                            result.xdmf_path.c_str()));
  } catch (const std::exception& e) {
    PetscCall(PetscPrintf(comm, "dipc: error: %s\n", e.what()));
    status = 1;
  }
  PetscCall(PetscFinalize());
  MPI_Finalize();
  return status;
}
