// run_scene: a whole dipc run — build and partition the mesh, set up the problem, step in
// time, report and write output. The `dipc` program is a thin wrapper around it; tests call it
// on sub-communicators to compare rank counts.
#pragma once
#include <petscsys.h>

#include <string>
#include <vector>

#include "app/run_options.hpp"
#include "io/scene.hpp"

namespace dipc {

struct RunResult {
  int steps_taken = 0;
  std::string failure;  // why the run stopped early; empty if it completed
  // On rank 0 of the run's communicator: final positions and velocities, 3 per node of the
  // input mesh (input numbering, independent of the partition).
  std::vector<double> positions, velocities;
  std::string xdmf_path;  // empty without output
};

// Collective over comm. Input errors (mesh file, selections) throw std::runtime_error with the
// same message on every rank; PETSc failures return an error code.
PetscErrorCode run_scene(const Scene& scene, MPI_Comm comm, const RunOptions& options, RunResult* result);

}  // namespace dipc
