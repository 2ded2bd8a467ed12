// Conservation in free flight (no gravity, contact or Dirichlet nodes): a soft box thrown and
// spun, so that it deforms while it tumbles.
//  - Linear momentum: implicit Euler gives M(v_{n+1} − v_n) = h f_int(x_{n+1}), and the
//    internal forces of a translation-invariant energy sum to zero, so Σ m v is conserved up to
//    the Newton residual.
//  - Angular momentum: with x_{n+1} = x_n + h v_{n+1},
//      L_{n+1} − L_n = Σ x_{n+1} × m(v_{n+1} − v_n) + h Σ m v_{n+1} × v_n,
//    whose first sum is h Σ x × f_int = 0 for a rotation-invariant energy. Implicit Euler does
//    not conserve L: it loses h Σ m v_{n+1} × v_n per step (numerical damping of the spin).
//    The test checks that balance to the solver's tolerance, and that L does decay.
// Run on 1 and 2 ranks (the sums are over all ranks).
#include <gtest/gtest.h>

#include <cmath>

#include "mesh/box_generator.hpp"
#include "nonlinear/step_recovery.hpp"
#include "partition/distributed_mesh.hpp"
#include "static_problem.hpp"

namespace dipc {
namespace {

std::array<double, 3> cross(const double* a, const double* b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

double norm(const std::array<double, 3>& a) { return std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]); }

TEST(Conservation, FreeFlightKeepsMomentumAndLosesSpinOnlyThroughTheIntegrator) {
  testing::set_tight_solver_options();
  const HexMesh whole = generate_box({0.2, 0.1, 0.1}, {4, 2, 2}, {-0.1, -0.05, -0.05}, 0, "box");
  DistributedMesh mesh = distribute_mesh(whole, PETSC_COMM_WORLD);
  const double E = 1e5, nu = 0.3, rho = 1000, h = 0.01;
  ProblemSetup problem;
  problem.body_materials = {{E * nu / ((1 + nu) * (1 - 2 * nu)), E / (2 * (1 + nu)), rho}};
  problem.body_velocity = {{1.0, 0.0, 0.5}};
  problem.body_angular_velocity = {{0.0, 3.0, 20.0}};
  problem.body_spin_center = {{0.0, 0.0, 0.0}};
  problem.dt = h;
  StepControl control;
  control.velocity_tol = 1e-10;  // m/s
  TimeIntegrator integrator;
  ASSERT_EQ(integrator.setup(mesh, problem, control), 0);
  StepRecovery recovery(integrator, h);

  const auto& mass = integrator.node_masses();
  const std::size_t n = mass.size();
  PhysicalQuantities q0, before, after;
  ASSERT_EQ(integrator.measure(&q0), 0);
  before = q0;
  double worst_momentum = 0, worst_balance = 0, largest_loss = 0;
  for (int step = 0; step < 10; ++step) {
    std::vector<double> v_old(3 * n);
    const PetscScalar* v;
    VecGetArrayRead(integrator.velocities(), &v);
    v_old.assign(v, v + 3 * n);
    VecRestoreArrayRead(integrator.velocities(), &v);

    StepReport report;
    ASSERT_EQ(recovery.step(&report), 0);
    ASSERT_TRUE(report.failure.empty()) << report.failure;
    ASSERT_EQ(integrator.measure(&after), 0);

    // h Σ m v_{n+1} × v_n over all ranks.
    double loss_local[3] = {0, 0, 0}, loss[3];
    VecGetArrayRead(integrator.velocities(), &v);
    for (std::size_t i = 0; i < n; ++i) {
      const auto c = cross(v + 3 * i, v_old.data() + 3 * i);
      for (int k = 0; k < 3; ++k) loss_local[k] += h * mass[i] * c[k];
    }
    VecRestoreArrayRead(integrator.velocities(), &v);
    MPI_Allreduce(loss_local, loss, 3, MPI_DOUBLE, MPI_SUM, PETSC_COMM_WORLD);

    std::array<double, 3> dP, residual;
    for (int k = 0; k < 3; ++k) {
      dP[k] = after.momentum[k] - q0.momentum[k];
      residual[k] = after.angular_momentum[k] - before.angular_momentum[k] - loss[k];
    }
    worst_momentum = std::max(worst_momentum, norm(dP) / norm(q0.momentum));
    worst_balance = std::max(worst_balance, norm(residual) / norm(q0.angular_momentum));
    largest_loss = std::max(largest_loss, norm({loss[0], loss[1], loss[2]}) / norm(q0.angular_momentum));
    before = after;
  }
  std::printf("free flight, 10 steps: |dP|/|P| %.2e, angular balance residual %.2e, spin loss per step up to %.2e "
              "of |L0|, |L| %.6g -> %.6g\n",
              worst_momentum, worst_balance, largest_loss, norm(q0.angular_momentum), norm(after.angular_momentum));
  EXPECT_LT(worst_momentum, 1e-9);
  EXPECT_LT(worst_balance, 1e-7);
  EXPECT_GT(largest_loss, 100 * worst_balance) << "the balance is checked against a loss that is not there";
  EXPECT_LT(norm(after.angular_momentum), norm(q0.angular_momentum));
  testing::clear_solver_options();
}

}  // namespace
}  // namespace dipc
