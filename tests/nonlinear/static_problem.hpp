// Test support: static solves on generated meshes through the real stack (METIS partition,
// forms, SNES), returning the solution gathered by input node id on every rank.
#pragma once
#include <petscsys.h>

#include <vector>

#include "mesh/hex_mesh.hpp"
#include "nonlinear/step_recovery.hpp"
#include "nonlinear/time_integrator.hpp"
#include "partition/distributed_mesh.hpp"

namespace dipc::testing {

// Tight solver tolerances, so tests measure discretisation, not solver, error.
inline void set_tight_solver_options() {
  PetscOptionsSetValue(nullptr, "-ksp_rtol", "1e-13");
  PetscOptionsSetValue(nullptr, "-ksp_atol", "1e-50");
  PetscOptionsSetValue(nullptr, "-ksp_max_it", "2000");
  PetscOptionsSetValue(nullptr, "-snes_rtol", "1e-14");
}

inline void clear_solver_options() {
  for (const char* o : {"-ksp_rtol", "-ksp_atol", "-ksp_max_it", "-snes_rtol"}) PetscOptionsClearValue(nullptr, o);
}

// Runs `steps` static load steps of `problem` (Dirichlet sets given as input node ids are
// translated to local ids here) on `whole` (significant on rank 0 only), and returns the final
// positions, 3 per input node, on every rank.
struct InputDirichlet {
  std::vector<std::int64_t> input_nodes;
  PrescribedMotion motion;
};

inline std::vector<double> solve_static(const HexMesh& whole, ProblemSetup problem,
                                        const std::vector<InputDirichlet>& bcs, double tolerance,
                                        StepReport* last = nullptr) {
  MPI_Comm comm = PETSC_COMM_WORLD;
  DistributedMesh mesh = distribute_mesh(whole, comm);
  problem.dirichlet.clear();
  for (const auto& bc : bcs) {
    DirichletSet set;
    set.motion = bc.motion;
    std::vector<char> wanted(mesh.num_global_nodes, 0);
    for (auto n : bc.input_nodes) wanted[n] = 1;
    for (int n = 0; n < mesh.num_local_nodes(); ++n)
      if (wanted[mesh.node_input_id[n]]) set.local_nodes.push_back(n);
    problem.dirichlet.push_back(set);
  }
  TimeIntegrator integrator;
  StepControl control;
  control.velocity_tol = tolerance;
  if (integrator.setup(mesh, problem, control)) throw std::runtime_error("setup failed");
  StepRecovery recovery(integrator, problem.dt / 1024);
  StepReport report;
  for (int s = 0; s < problem.steps; ++s) {
    if (recovery.step(&report)) throw std::runtime_error("step failed");
    if (!report.failure.empty()) throw std::runtime_error(report.failure);
  }
  if (last) *last = report;
  std::vector<double> mine(3 * mesh.num_global_nodes, 0.0), all(mine.size());
  const PetscScalar* x;
  VecGetArrayRead(integrator.positions(), &x);
  for (int n = 0; n < mesh.num_owned_nodes; ++n)
    for (int c = 0; c < 3; ++c) mine[3 * mesh.node_input_id[n] + c] = x[3 * n + c];
  VecRestoreArrayRead(integrator.positions(), &x);
  MPI_Allreduce(mine.data(), all.data(), static_cast<int>(all.size()), MPI_DOUBLE, MPI_SUM, comm);
  return all;
}

inline int comm_rank() {
  int r;
  MPI_Comm_rank(PETSC_COMM_WORLD, &r);
  return r;
}

}  // namespace dipc::testing
