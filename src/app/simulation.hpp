// run_scene: a whole dipc run — build and partition the mesh, set up the problem, step in
// time, report and write output. The `dipc` program is a thin wrapper around it; tests call it
// on sub-communicators to compare rank counts. Simulation is the same run a step at a time.
#pragma once
#include <petscsys.h>

#include <memory>
#include <string>
#include <vector>

#include "app/run_options.hpp"
#include "io/scene.hpp"
#include "nonlinear/time_integrator.hpp"
#include "partition/distributed_mesh.hpp"

namespace dipc {

// Wall time per phase of a run, the slowest rank's (seconds); the rows of the timing table.
// Each is measured on every rank from disjoint intervals, or is a remainder of an enclosing
// wall time (linear_solve, other), so none is negative. A phase the run does not have is 0.
struct PhaseTimes {
  double partition = 0, setup = 0;  // setup: problem, forms, the first matrix, solver setup
  double assembly = 0;              // gradient and Hessian evaluation in the solves, COO insertion included
  double coo_insert = 0;            // MatSetValuesCOO alone
  double line_search = 0;           // energy and validity of trial states, gathering each segment
  double contact = 0;               // ghost-surface exchange, broad phase and CCD (the barrier is in assembly)
  double preallocation = 0;         // new matrices for patterns that changed after setup (contact)
  double linear_solve = 0;          // the rest of the Newton solves: KSP, AMG setup, vector work
  double output = 0;
  double other = 0;  // the rest of the run: step reports, energies and checks between solves
  double total = 0;
};

struct RunResult {
  int steps_taken = 0;
  std::string failure;    // why the run stopped early; empty if it completed
  bool fatal = false;     // the failure is a violated invariant (not a step recovery could not take)
  long long dt_cuts = 0;  // failed attempts retried with a halved step
  // On rank 0 of the run's communicator: final positions and velocities, 3 per node of the
  // input mesh (input numbering, independent of the partition).
  std::vector<double> positions, velocities;
  std::string xdmf_path;          // empty without output
  int stop_signal = 0;            // the signal that stopped the run (0: none)
  double stop_seconds = 0;        // from the signal to its checkpoint written (max over ranks)
  std::string checkpoint_path;    // the last checkpoint written (empty: none)
  double checkpoint_seconds = 0;  // writing checkpoints (part of the output time)
  PhaseTimes times;
  long long newton_iterations = 0, linear_iterations = 0;
  long long preconditioner_rebuilds = 0;  // decided by -dipc_pc_reuse (0 when it is off)
  // -dipc_contact_exact_hessian: Newton iterations with unprojected contact Hessians, and the
  // solves in which one failed (newton_solver.hpp)
  long long exact_hessian_iterations = 0, exact_hessian_fallbacks = 0;
  long long num_elements = 0, num_dofs = 0;
  int openmp_threads = 0;                // per rank, as set for the libraries (openmp_threads.hpp; 0: unknown)
  long max_contact_pairs = 0;            // over the steps (contact runs)
  long new_matrix_patterns = 0;          // matrices made after setup because a pattern changed (contact)
  long pattern_remaps = 0;               // changed patterns that fitted the matrix (no new matrix)
  std::vector<std::string> timing_rows;  // the timing table's rows: the phases this run has
};

// Collective over comm. Input errors (mesh file, selections) throw std::runtime_error with the
// same message on every rank; PETSc failures return an error code.
PetscErrorCode run_scene(const Scene& scene, MPI_Comm comm, const RunOptions& options, RunResult* result);

// Collective: an owned-node field (3 per node, e.g. TimeIntegrator::positions()) gathered on
// rank 0 of mesh.comm in the input mesh's numbering (empty on the other ranks).
PetscErrorCode gather_by_input_id(const DistributedMesh& mesh, Vec field, std::vector<double>* out);

// A run taken one scene step at a time: what run_scene does, with the state reachable between
// steps (the Python module drives it; python/README.md). Every call is collective over comm and
// reports errors as run_scene does.
class Simulation {
 public:
  // Partition, setup, run header, restart (-dipc_restart) and the first output frame.
  static PetscErrorCode create(const Scene& scene, MPI_Comm comm, const RunOptions& options,
                               std::unique_ptr<Simulation>* simulation);
  ~Simulation();
  Simulation(const Simulation&) = delete;
  Simulation& operator=(const Simulation&) = delete;

  // The step boundary (a stop signal, a due checkpoint), then one scene step with its output
  // and console line. *report is that step's (report->step == 0 when no step was taken: the run
  // had ended at this boundary). A step that failed, the run's last step or a stop signal
  // ends the run: ended() is true and progress() says why.
  PetscErrorCode step(StepReport* report);
  bool ended() const;
  // The counts, failure and stop of the run so far (RunResult's step fields; the rest once
  // finish() has run).
  const RunResult& progress() const;
  // The end of the run: the last boundary's checkpoint when one is due, the final fields
  // gathered on rank 0 and the timing table. Once; no step after it.
  PetscErrorCode finish(RunResult* result);

  const Scene& scene() const;  // as run: refined by -dipc_refine
  int steps_taken() const;
  int last_step() const;  // the run's number of steps (-dipc_steps or the scene's)
  TimeIntegrator& integrator();
  const DistributedMesh& mesh() const;

 private:
  struct Impl;
  explicit Simulation(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace dipc
