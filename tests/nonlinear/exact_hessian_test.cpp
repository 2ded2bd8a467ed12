// -dipc_contact_exact_hessian's schedule and fallback (newton_solver.hpp), on a cantilever bent
// by its weight far into the nonlinear range, solved by the real NewtonSolver on 1 and 2 ranks.
// The forms include a test inertia whose "exact" Hessian is chosen by the test, standing in for
// the contact pairs' unprojected Hessians:
//  - the same values as its projected one: with the option the solve takes the exact Hessian in
//    every iteration from the third on (none before, the pattern never changes here) and is bit
//    for bit the solve without it;
//  - an indefinite one (-0.5, -10 and -1e6 times its own: CG stops on an indefinite matrix, on an
//    indefinite BoomerAMG, or converges to an ascent direction): every such direction is
//    dropped without moving, the solve projects for 2, then 4, ... iterations before it tries
//    again, and it ends at the minimiser the solve without the option reaches, in one Newton
//    iteration more per try;
//  - a plain inertia (no form with projected terms): the option changes nothing, and no
//    iteration counts as exact; nor does a retry's solve (NewtonSolver::set_retrying, step
//    recovery's), whose CG also stops 10 times tighter.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>
#include <vector>

#include "forms/body_force_form.hpp"
#include "forms/elastic_form.hpp"
#include "forms/inertia_form.hpp"
#include "mesh/box_generator.hpp"
#include "nonlinear/newton_solver.hpp"
#include "partition/distributed_mesh.hpp"
#include "potential/incremental_potential.hpp"

namespace dipc {
namespace {

// Lumped inertia whose Hessian, while set_exact_hessian(true) holds, is its own diagonal times
// `exact_scale` (1: the same matrix; a large negative number: an indefinite total Hessian).
class InertiaWithChosenExactHessian : public LumpedInertiaForm {
 public:
  InertiaWithChosenExactHessian(std::vector<double> mass, int owned, std::int64_t offset, double exact_scale)
      : LumpedInertiaForm(std::move(mass), owned, offset), exact_scale_(exact_scale) {}
  bool set_exact_hessian(bool exact) override {
    exact_ = exact;
    return true;
  }
  bool hessian(const double* x, double* values) override {
    const bool ok = LumpedInertiaForm::hessian(x, values);
    if (exact_) {
      std::vector<PetscInt> rows, cols;
      coo_pattern(&rows, &cols);
      for (std::size_t k = 0; k < rows.size(); ++k) values[k] *= exact_scale_;
    }
    return ok;
  }

 private:
  double exact_scale_;
  bool exact_ = false;
};

struct Solved {
  NewtonReport report;
  PetscReal rtol = 0;     // CG's relative tolerance during the solve
  std::vector<double> x;  // this rank's owned positions
};

// One implicit step of a soft 2 m x 0.25 m x 0.25 m cantilever (clamped at x = 0) released at
// rest under 20 g, with the option on or off; without exact_scale, with a plain inertia.
Solved solve_cantilever(bool exact_option, std::optional<double> exact_scale, bool retrying = false) {
  MPI_Comm comm = PETSC_COMM_WORLD;
  HexMesh whole = generate_box({2, 0.25, 0.25}, {16, 2, 2}, {0, 0, 0}, 0, "beam");
  DistributedMesh mesh = distribute_mesh(whole, comm);
  const double h = 0.1, rho = 1000;
  BodyMaterial material{/*lambda*/ 4e5, /*mu*/ 2e5, rho};
  ElementData elements(mesh, {material});
  // One uniform node mass (an element's mass), enough for a test inertia and the weight.
  const double node_mass = rho * (2.0 / 16) * (0.25 / 2) * (0.25 / 2);
  std::vector<double> mass(mesh.num_local_nodes(), node_mass);
  std::vector<std::unique_ptr<Form>> forms;
  if (exact_scale)
    forms.push_back(
        std::make_unique<InertiaWithChosenExactHessian>(mass, mesh.num_owned_nodes, mesh.node_offset, *exact_scale));
  else
    forms.push_back(std::make_unique<LumpedInertiaForm>(mass, mesh.num_owned_nodes, mesh.node_offset));
  forms.push_back(std::make_unique<ElasticForm>(elements, h * h));
  forms.push_back(std::make_unique<BodyForceForm>(mass, mesh.num_owned_nodes, std::array<double, 3>{0, 0, -196.2}, h * h));
  std::vector<char> prescribed(3 * mesh.num_local_nodes(), 0);
  for (std::int32_t n : mesh.node_sets.at("beam.xmin")) prescribed[3 * n] = prescribed[3 * n + 1] = prescribed[3 * n + 2] = 1;
  IncrementalPotential potential;
  EXPECT_EQ(potential.setup(mesh, std::move(forms), prescribed), 0);

  Vec x;
  potential.create_global_vec(&x);
  PetscScalar* xa;
  VecGetArray(x, &xa);
  for (int n = 0; n < mesh.num_owned_nodes; ++n)
    for (int c = 0; c < 3; ++c) xa[3 * n + c] = mesh.coordinates[n][c];
  VecRestoreArray(x, &xa);
  EXPECT_EQ(potential.begin_step(x), 0);  // x̂ = rest: released at rest

  PetscOptionsSetValue(nullptr, "-dipc_contact_exact_hessian", exact_option ? "1" : "0");
  Solved out;
  {
    NewtonSolver solver;
    EXPECT_EQ(solver.setup(comm, &potential, x, h, /*velocity_tol*/ 1e-9, /*alpha_floor*/ 1e-6), 0);
    EXPECT_EQ(solver.set_retrying(retrying), 0);
    KSP ksp;
    PetscReal abstol, dtol;
    PetscInt max_it;
    SNESGetKSP(solver.snes(), &ksp);
    KSPGetTolerances(ksp, &out.rtol, &abstol, &dtol, &max_it);
    EXPECT_EQ(solver.solve(x, &out.report), 0);
  }
  PetscOptionsClearValue(nullptr, "-dipc_contact_exact_hessian");
  const PetscScalar* xr;
  PetscInt n;
  VecGetLocalSize(x, &n);
  VecGetArrayRead(x, &xr);
  out.x.assign(xr, xr + n);
  VecRestoreArrayRead(x, &xr);
  VecDestroy(&x);
  return out;
}

TEST(ExactHessian, TakenFromTheThirdIterationOfASettledSolveAndOtherwiseTheSameSolve) {
  const Solved projected = solve_cantilever(false, 1.0);
  ASSERT_GT(projected.report.reason, 0) << projected.report.ended_by;
  ASSERT_GE(projected.report.iterations, 4) << "the test needs a solve of several Newton iterations";
  EXPECT_EQ(projected.report.exact_hessian_iterations, 0);

  const Solved exact = solve_cantilever(true, 1.0);
  ASSERT_GT(exact.report.reason, 0) << exact.report.ended_by;
  EXPECT_EQ(exact.report.iterations, projected.report.iterations);
  // Iterations 2, 3, ... up to the last one that solved a system (the last iteration only tests).
  EXPECT_EQ(exact.report.exact_hessian_iterations, projected.report.iterations - 2);
  EXPECT_EQ(exact.report.exact_hessian_fallbacks, 0);
  EXPECT_EQ(exact.report.linear_iterations, projected.report.linear_iterations);
  EXPECT_TRUE(exact.x == projected.x) << "the same matrices gave different iterates";
}

class IndefiniteExactHessian : public ::testing::TestWithParam<double> {};

TEST_P(IndefiniteExactHessian, IsDroppedAndTheSolveProjectsToTheSameMinimiser) {
  const Solved projected = solve_cantilever(false, 1.0);
  ASSERT_GT(projected.report.reason, 0) << projected.report.ended_by;
  const Solved fallback = solve_cantilever(true, GetParam());
  ASSERT_GT(fallback.report.reason, 0) << fallback.report.ended_by;
  // Tries at iterations 2, 5 (2 projected after the first failure), 10 (4 after the second), ...
  const PetscInt tries = fallback.report.exact_hessian_iterations;
  EXPECT_GE(tries, 2) << "the test should see the solve try again";
  EXPECT_EQ(fallback.report.exact_hessian_fallbacks, tries);
  EXPECT_EQ(fallback.report.iterations, projected.report.iterations + tries);
  PetscInt expected_tries = 0;
  for (PetscInt at = 2, wait = 2; at < fallback.report.iterations; at += 1 + wait, wait *= 2) ++expected_tries;
  EXPECT_EQ(tries, expected_tries);
  double diff = 0, scale = 0;
  for (std::size_t k = 0; k < projected.x.size(); ++k) {
    diff = std::max(diff, std::abs(fallback.x[k] - projected.x[k]));
    scale = std::max(scale, std::abs(projected.x[k]));
  }
  MPI_Allreduce(MPI_IN_PLACE, &diff, 1, MPI_DOUBLE, MPI_MAX, PETSC_COMM_WORLD);
  // Both end with |p|_inf < 1e-9 h: the minimisers agree far below that.
  EXPECT_LT(diff, 1e-8) << "the fallback solve ended elsewhere";
}

INSTANTIATE_TEST_SUITE_P(ExactHessian, IndefiniteExactHessian, ::testing::Values(-0.5, -10.0, -1e6));

// Step recovery's retries (set_retrying): no iteration takes the exact Hessian, and CG stops at
// a tenth of the relative tolerance; the solve is the projected one at that tolerance.
TEST(ExactHessian, ARetryNeverTakesItAndSolvesTighter) {
  const Solved first = solve_cantilever(false, 1.0);
  const Solved projected = solve_cantilever(false, 1.0, /*retrying=*/true);
  const Solved retry = solve_cantilever(true, -1e6, /*retrying=*/true);
  ASSERT_GT(retry.report.reason, 0) << retry.report.ended_by;
  EXPECT_EQ(retry.report.exact_hessian_iterations, 0);
  EXPECT_DOUBLE_EQ(retry.rtol, 0.1 * first.rtol);
  EXPECT_EQ(retry.report.iterations, projected.report.iterations);
  EXPECT_TRUE(retry.x == projected.x);
}

TEST(ExactHessian, ChangesNothingWithoutAFormThatProjects) {
  const Solved off = solve_cantilever(false, std::nullopt);
  const Solved on = solve_cantilever(true, std::nullopt);
  ASSERT_GT(on.report.reason, 0) << on.report.ended_by;
  EXPECT_EQ(on.report.exact_hessian_iterations, 0);
  EXPECT_EQ(on.report.iterations, off.report.iterations);
  EXPECT_TRUE(on.x == off.x);
}

}  // namespace
}  // namespace dipc
