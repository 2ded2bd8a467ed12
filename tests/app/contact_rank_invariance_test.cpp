// Contact across ranks: the default scene (a soft cube dropped on a box resting on a ground
// plane; METIS puts the contact zone on a partition boundary) run on all ranks of the test's
// communicator and on rank 0 alone gives the same trajectory: relative difference of the
// displacements ≤ 1e-6 after 20 steps, with tight solver tolerances. Invariants (no inverted
// element, no intersection, positive distance) are checked after every step. The parallel run
// uses METIS, then PT-Scotch.
#include <gtest/gtest.h>

#include "app/simulation.hpp"
#include "displacement_difference.hpp"
#include "partition/slice_partition.hpp"

namespace dipc {
namespace {

void default_scene_matches_one_rank(const char* partitioner) {
  MPI_Comm world = PETSC_COMM_WORLD;
  int rank, size;
  MPI_Comm_rank(world, &rank);
  MPI_Comm_size(world, &size);
  PetscOptionsSetValue(nullptr, "-ksp_rtol", "1e-12");
  PetscOptionsSetValue(nullptr, "-ksp_max_it", "5000");

  const Scene scene = default_scene();
  RunOptions options;
  options.steps = 20;  // the cube lands at step 10
  options.write_output = false;
  options.quiet = true;
  options.report = false;
  options.check_invariants = true;
  options.velocity_tol = 1e-7;  // m/s: Newton steps below 1e-9 m
  options.partitioner = partitioner;

  RunResult parallel;
  ASSERT_EQ(run_scene(scene, world, options, &parallel), 0);
  ASSERT_TRUE(parallel.failure.empty()) << parallel.failure;
  EXPECT_GT(parallel.max_contact_pairs, 100) << "the bodies never touched: the comparison would be vacuous";

  MPI_Comm self;
  MPI_Comm_split(world, rank == 0 ? 0 : MPI_UNDEFINED, 0, &self);
  if (rank == 0) {
    RunResult serial, reference;
    ASSERT_EQ(run_scene(scene, self, options, &serial), 0);
    ASSERT_TRUE(serial.failure.empty()) << serial.failure;
    RunOptions zero = options;
    zero.setup_only = true;
    ASSERT_EQ(run_scene(scene, self, zero, &reference), 0);
    const DisplacementDifference d = displacement_difference(serial, parallel, reference);
    std::printf("contact, %s, ranks %d vs 1: max |u_N - u_1| = %.3e, max |u_1| = %.3e, relative %.3e\n", partitioner,
                size, d.max_difference, d.max_displacement, d.relative());
    EXPECT_GT(d.max_displacement, 1e-2);
    EXPECT_LE(d.relative(), 1e-6);
    MPI_Comm_free(&self);
  }
  for (const char* o : {"-ksp_rtol", "-ksp_max_it"}) PetscOptionsClearValue(nullptr, o);
}

TEST(ContactRankInvariance, DefaultSceneTwentyStepsMatchesOneRank) { default_scene_matches_one_rank("metis"); }

// PT-Scotch puts the contact zone on other rank boundaries; the ghost surfaces must follow.
TEST(ContactRankInvariance, DefaultScenePtScotchMatchesOneRank) {
  if (!ptscotch_available()) GTEST_SKIP() << "this PETSc has no PT-Scotch";
  default_scene_matches_one_rank("ptscotch");
}

// RCB cuts by centroid, without the dual graph: the ghost surfaces must follow it too.
TEST(ContactRankInvariance, DefaultSceneRcbMatchesOneRank) { default_scene_matches_one_rank("rcb"); }

}  // namespace
}  // namespace dipc
