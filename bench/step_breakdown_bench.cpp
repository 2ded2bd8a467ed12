// Benchmark: where the time of a whole implicit step goes, on a clamped box of N hex8
// elements swinging under gravity (the default scene's physics, scaled up). Prints a table per
// N and writes CSV: partition, setup, assembly (of which COO insertion), line search, AMG
// setup, KSP solve, output, per Newton iteration where it makes sense.
//
//   mpirun -n R bench_step_breakdown [-elements 10000,100000] [-steps 3] [-csv out.csv]
//                                    [-dipc_backend cpu|cuda|auto] [PETSc options]
// With -vec_type cuda -mat_type aijcusparse (a CUDA PETSc) vectors and matrix stay on the device.
// The solver settings are the program's: -dipc_preset (balanced when not given) fills in what
// the command line leaves unset, and -dipc_velocity_tol_rel etc. are read as dipc reads them.
#include <petscksp.h>
#include <sys/resource.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "app/run_options.hpp"
#include "app/simulation.hpp"
#include "app/solver_presets.hpp"
#include "logging/log_stages.hpp"

namespace {

// A box about 4:1:1 with n_x·n_y·n_z ≈ N cubic elements, clamped at x = 0.
dipc::Scene box_scene(long long elements) {
  dipc::Scene s;
  s.source = "<bench box>";
  s.materials.push_back({"rubber", 1e6, 0.4, 1000});
  dipc::Body b;
  b.name = "box";
  const int n = std::max(1, static_cast<int>(std::lround(std::cbrt(elements / 4.0))));
  b.box = dipc::BoxGenerator{{4.0, 1.0, 1.0}, {4 * n, n, n}, {0, 0, 0}};
  s.bodies.push_back(b);
  s.gravity = {0, 0, -9.81};
  dipc::DirichletCondition clamp;
  clamp.selection.name = "box.xmin";
  clamp.key_path = "bench";
  s.dirichlet.push_back(clamp);
  s.dt = 0.01;
  s.steps = 3;
  return s;
}

// Seconds (or, with count, calls) of a PETSc event in dipc's solve and assembly stages, on the
// slowest rank.
double event_seconds(const char* name, bool count = false) {
  PetscLogEvent id;
  PetscEventPerfInfo info;
  if (PetscLogEventGetId(name, &id)) return 0;
  double total = 0;
  // A stage that has not run yet has no record of the event: PETSc returns an error, which is
  // not one here (PETSc >= 3.20 would print it through the default handler).
  PetscPushErrorHandler(PetscReturnErrorHandler, nullptr);
  for (PetscLogStage st : {dipc::log_stages().solve, dipc::log_stages().assembly}) {
    if (PetscLogEventGetPerfInfo(st, id, &info)) continue;
    total += count ? info.count : info.time;
  }
  PetscPopErrorHandler();
  double worst = 0;
  MPI_Allreduce(&total, &worst, 1, MPI_DOUBLE, MPI_MAX, PETSC_COMM_WORLD);
  return worst;
}

}  // namespace

int main(int argc, char** argv) {
  PetscCall(PetscInitialize(&argc, &argv, nullptr, "dipc step-breakdown benchmark\n"));
  PetscCall(PetscLogDefaultBegin());
  PetscInt sizes[16] = {10000, 100000};
  PetscInt nsizes = 16, steps = 3;
  char csv_path[PETSC_MAX_PATH_LEN] = "";
  PetscBool has_sizes = PETSC_FALSE;
  PetscCall(PetscOptionsGetIntArray(nullptr, nullptr, "-elements", sizes, &nsizes, &has_sizes));
  if (!has_sizes) nsizes = 2;
  PetscCall(PetscOptionsGetInt(nullptr, nullptr, "-steps", &steps, nullptr));
  PetscCall(PetscOptionsGetString(nullptr, nullptr, "-csv", csv_path, sizeof(csv_path), nullptr));
  char backend[16] = "cpu", mat_type[64] = "aij";
  PetscCall(PetscOptionsGetString(nullptr, nullptr, "-dipc_backend", backend, sizeof(backend), nullptr));
  PetscCall(PetscOptionsGetString(nullptr, nullptr, "-mat_type", mat_type, sizeof(mat_type), nullptr));
  std::string preset;
  std::vector<std::string> preset_inserted;
  PetscCall(dipc::apply_solver_preset(PETSC_COMM_WORLD, &preset, &preset_inserted));
  int ranks, rank;
  MPI_Comm_size(PETSC_COMM_WORLD, &ranks);
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);

  FILE* csv = nullptr;
  if (rank == 0 && csv_path[0]) {
    csv = std::fopen(csv_path, "w");
    if (!csv) {
      std::fprintf(stderr, "bench_step_breakdown: cannot write %s\n", csv_path);
      PetscCall(PetscFinalize());
      return 1;
    }
    std::fprintf(
        csv, "backend,mat_type,ranks,elements,dofs,steps,newton_its,ksp_its,partition_s,setup_s,assembly_s,"
             "coo_insert_s,line_search_s,contact_s,amg_setup_s,ksp_solve_s,total_s,per_newton_s,pc_setups,per_step_s,"
             "threads_per_rank\n");
  }
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "backend %s, Mat %s, solver preset %s\n", backend, mat_type, preset.c_str()));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%6s %9s %9s %6s %6s | %9s %9s %9s %9s %9s %9s | %9s\n", "ranks", "elements",
                        "dofs", "newton", "ksp", "assembly", "coo_ins", "lsearch", "amg_setup", "ksp_solve", "total",
                        "s/newton"));
  for (PetscInt i = 0; i < nsizes; ++i) {
    dipc::Scene scene = box_scene(sizes[i]);
    dipc::RunOptions options;  // the -dipc_ options, with this scene's defaults
    PetscCall(dipc::read_run_options(PETSC_COMM_WORLD, scene, &options));
    options.steps = static_cast<int>(steps);
    options.write_output = false;
    options.quiet = true;
    options.report = false;
    options.backend = backend;
    const double pc0 = event_seconds("PCSetUp"), ksp0 = event_seconds("KSPSolve");
    const double setups0 = event_seconds("PCSetUp", true);
    dipc::RunResult r;
    PetscCall(dipc::run_scene(scene, PETSC_COMM_WORLD, options, &r));
    const double pc = event_seconds("PCSetUp") - pc0, ksp = event_seconds("KSPSolve") - ksp0;
    const long long setups = std::llround(event_seconds("PCSetUp", true) - setups0);
    const auto& t = r.times;
    // Per Newton iteration and per step: a cheaper iteration (looser CG, reused AMG) can take
    // more iterations per step, so both are written.
    const double solve_time = t.assembly + t.line_search + t.linear_solve;
    const double per_newton = r.newton_iterations ? solve_time / r.newton_iterations : 0;
    PetscCall(
        PetscPrintf(PETSC_COMM_WORLD, "%6d %9lld %9lld %6lld %6lld | %9.3f %9.3f %9.3f %9.3f %9.3f %9.3f | %9.4f%s\n",
                    ranks, r.num_elements, r.num_dofs, r.newton_iterations, r.linear_iterations, t.assembly,
                    t.coo_insert, t.line_search, pc, ksp, t.total, per_newton, r.failure.empty() ? "" : "  (FAILED)"));
    if (csv)
      std::fprintf(csv,
                   "%s,%s,%d,%lld,%lld,%d,%lld,%lld,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%lld,%.6f,%d\n",
                   backend, mat_type, ranks, r.num_elements, r.num_dofs, (int)steps, r.newton_iterations,
                   r.linear_iterations, t.partition, t.setup, t.assembly, t.coo_insert, t.line_search, t.contact, pc,
                   ksp, t.total, per_newton, setups, solve_time / steps, r.openmp_threads);
  }
  if (csv) std::fclose(csv);
  // Peak host memory of the largest rank over all sizes (getrusage: kilobytes on Linux).
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  long peak_kb = usage.ru_maxrss, most = 0;
  MPI_Allreduce(&peak_kb, &most, 1, MPI_LONG, MPI_MAX, PETSC_COMM_WORLD);
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "peak host memory of a rank: %.2f GB\n", most / 1048576.0));
  PetscCall(PetscFinalize());
  return 0;
}
