// -dipc_pc_reuse (keep the preconditioner while that pays) on the default scene, which has
// contact and so changes the Hessian's pattern: the run keeps its preconditioner across
// iterations (fewer rebuilds than Newton iterations), ends where the run that rebuilds at
// every iteration ends, to well within the Newton tolerance, and, since its decisions come
// from CG iteration counts and not from clocks, a second run ends bit for bit where the first
// did. On the test's ranks (1 and 2). A change of the contact active set that keeps the matrix
// (-dipc_pattern_remap fit) rebuilds the preconditioner as a new matrix does.
#include <gtest/gtest.h>
#include <petscsys.h>

#include <cstdio>

#include "app/simulation.hpp"
#include "colliding_blocks_scene.hpp"
#include "displacement_difference.hpp"
#include "io/default_scene.hpp"

namespace dipc {
namespace {

RunOptions twenty_quiet_steps() {
  RunOptions options;
  options.steps = 20;
  options.write_output = false;
  options.quiet = true;
  options.report = false;
  options.velocity_tol_rel = 1e-9;
  return options;
}

PetscErrorCode run_with_reuse(const Scene& scene, RunResult* result) {
  PetscOptionsSetValue(nullptr, "-dipc_pc_reuse", "1");
  const PetscErrorCode ierr = run_scene(scene, PETSC_COMM_WORLD, twenty_quiet_steps(), result);
  PetscOptionsClearValue(nullptr, "-dipc_pc_reuse");
  return ierr;
}

TEST(PcReuse, KeepsThePreconditionerAndReachesTheSameStatesReproducibly) {
  const Scene scene = default_scene();
  RunResult fresh, reused, again, rest;
  PetscOptionsSetValue(nullptr, "-dipc_pc_reuse", "0");  // explicit, whatever the default
  ASSERT_EQ(run_scene(scene, PETSC_COMM_WORLD, twenty_quiet_steps(), &fresh), 0);
  PetscOptionsClearValue(nullptr, "-dipc_pc_reuse");
  ASSERT_TRUE(fresh.failure.empty()) << fresh.failure;
  EXPECT_EQ(fresh.preconditioner_rebuilds, 0);  // the policy is off: SNES rebuilds, uncounted

  ASSERT_EQ(run_with_reuse(scene, &reused), 0);
  ASSERT_TRUE(reused.failure.empty()) << reused.failure;
  EXPECT_GE(reused.preconditioner_rebuilds, 1);
  EXPECT_LT(reused.preconditioner_rebuilds, reused.newton_iterations);

  // The same run again: the same decisions, iterations and final state, compared exactly.
  ASSERT_EQ(run_with_reuse(scene, &again), 0);
  ASSERT_TRUE(again.failure.empty()) << again.failure;
  EXPECT_EQ(again.preconditioner_rebuilds, reused.preconditioner_rebuilds);
  EXPECT_EQ(again.newton_iterations, reused.newton_iterations);
  EXPECT_EQ(again.linear_iterations, reused.linear_iterations);
  EXPECT_EQ(again.dt_cuts, reused.dt_cuts);
  EXPECT_TRUE(again.positions == reused.positions) << "final positions differ between two identical runs";
  EXPECT_TRUE(again.velocities == reused.velocities) << "final velocities differ between two identical runs";

  RunOptions zero = twenty_quiet_steps();
  zero.setup_only = true;
  ASSERT_EQ(run_scene(scene, PETSC_COMM_WORLD, zero, &rest), 0);
  int rank;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  if (rank == 0) {
    const DisplacementDifference d = displacement_difference(fresh, reused, rest);
    std::printf("pc reuse: %lld rebuilds in %lld Newton iterations (%lld without reuse), %lld/%lld CG iterations; "
                "max |u_reuse - u_fresh| / max |u| = %.3e; a second run %s\n",
                reused.preconditioner_rebuilds, reused.newton_iterations, fresh.newton_iterations,
                reused.linear_iterations, fresh.linear_iterations, d.relative(),
                again.positions == reused.positions ? "identical" : "DIFFERENT");
    ASSERT_FALSE(reused.positions.empty());
    EXPECT_GT(d.max_displacement, 0.0);
    EXPECT_LE(d.relative(), 1e-6);
  }
}

TEST(PcReuse, RebuildsThePreconditionerWhenTheActiveSetChangesWithinTheMatrix) {
  // Two blocks colliding with friction: their active set changes within the matrix's entries
  // at some iterations and outside them at others.
  const Scene scene = colliding_blocks_scene(8, 6);
  RunOptions options = twenty_quiet_steps();
  options.steps = 6;
  RunResult result;
  // A setup cost so high that the reuse policy never rebuilds for cost: what it rebuilds is
  // the first solve and the changes.
  PetscOptionsSetValue(nullptr, "-dipc_pc_reuse", "1");
  PetscOptionsSetValue(nullptr, "-dipc_pc_reuse_setup_cost", "1e9");
  PetscOptionsSetValue(nullptr, "-dipc_pattern_remap", "fit");
  const PetscErrorCode ierr = run_scene(scene, PETSC_COMM_WORLD, options, &result);
  PetscOptionsClearValue(nullptr, "-dipc_pc_reuse");
  PetscOptionsClearValue(nullptr, "-dipc_pc_reuse_setup_cost");
  PetscOptionsClearValue(nullptr, "-dipc_pattern_remap");
  std::printf("remap: %lld rebuilds in %lld Newton iterations, %ld new matrices, %ld remaps\n",
              result.preconditioner_rebuilds, result.newton_iterations, result.new_matrix_patterns,
              result.pattern_remaps);
  ASSERT_EQ(ierr, 0);
  ASSERT_TRUE(result.failure.empty()) << result.failure;
  ASSERT_GT(result.pattern_remaps, 0) << "no change kept the matrix: the test does not exercise the remap";
  // Every change, kept or not, is an iteration whose preconditioner is built afresh.
  EXPECT_GE(result.preconditioner_rebuilds, result.new_matrix_patterns + result.pattern_remaps);
}

TEST(PcReuse, RefusesAFixedLagAsWell) {
  PetscOptionsSetValue(nullptr, "-dipc_pc_reuse", "1");
  PetscOptionsSetValue(nullptr, "-snes_lag_preconditioner", "3");
  RunOptions options = twenty_quiet_steps();
  options.steps = 1;
  RunResult r;
  PetscPushErrorHandler(PetscReturnErrorHandler, nullptr);  // the error is the expected outcome
  const PetscErrorCode ierr = run_scene(default_scene(), PETSC_COMM_WORLD, options, &r);
  PetscPopErrorHandler();
  PetscOptionsClearValue(nullptr, "-dipc_pc_reuse");
  PetscOptionsClearValue(nullptr, "-snes_lag_preconditioner");
  EXPECT_EQ(ierr, PETSC_ERR_ARG_INCOMP);
}

}  // namespace
}  // namespace dipc
