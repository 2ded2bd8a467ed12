// -dipc_pc_reuse (keep the preconditioner while that pays) on the default scene, which has
// contact and so changes the Hessian's pattern: the run keeps its preconditioner across
// iterations (fewer rebuilds than Newton iterations) and ends where the run that rebuilds at
// every iteration ends, to well within the Newton tolerance. On the test's ranks (1 and 2).
#include <gtest/gtest.h>
#include <petscsys.h>

#include <cstdio>

#include "app/simulation.hpp"
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

TEST(PcReuse, KeepsThePreconditionerAndReachesTheSameStates) {
  const Scene scene = default_scene();
  RunResult fresh, reused, rest;
  ASSERT_EQ(run_scene(scene, PETSC_COMM_WORLD, twenty_quiet_steps(), &fresh), 0);
  ASSERT_TRUE(fresh.failure.empty()) << fresh.failure;
  EXPECT_EQ(fresh.preconditioner_rebuilds, 0);  // the policy is off: SNES rebuilds, uncounted

  PetscOptionsSetValue(nullptr, "-dipc_pc_reuse", "1");
  ASSERT_EQ(run_scene(scene, PETSC_COMM_WORLD, twenty_quiet_steps(), &reused), 0);
  PetscOptionsClearValue(nullptr, "-dipc_pc_reuse");
  ASSERT_TRUE(reused.failure.empty()) << reused.failure;
  EXPECT_GE(reused.preconditioner_rebuilds, 1);
  EXPECT_LT(reused.preconditioner_rebuilds, reused.newton_iterations);

  RunOptions zero = twenty_quiet_steps();
  zero.setup_only = true;
  ASSERT_EQ(run_scene(scene, PETSC_COMM_WORLD, zero, &rest), 0);
  int rank;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  if (rank == 0) {
    const DisplacementDifference d = displacement_difference(fresh, reused, rest);
    std::printf("pc reuse: %lld rebuilds in %lld Newton iterations (%lld without reuse), %lld/%lld CG iterations; "
                "max |u_reuse - u_fresh| / max |u| = %.3e\n",
                reused.preconditioner_rebuilds, reused.newton_iterations, fresh.newton_iterations,
                reused.linear_iterations, fresh.linear_iterations, d.relative());
    EXPECT_GT(d.max_displacement, 0.0);
    EXPECT_LE(d.relative(), 1e-6);
  }
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
