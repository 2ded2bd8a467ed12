// The partition's and the setup's host loops (threads/host_threads.hpp) on 1 and on 4 threads,
// through whole runs on 1 and 2 ranks: the same trajectory bit for bit (a cube resting on the
// contact plane: face matching, lumped masses, the contact surface and the start's intersection
// check all take several chunks), and the same report of an intersecting start (the first
// crossing and their count).
#include <gtest/gtest.h>

#include <string>

#include "app/simulation.hpp"
#include "io/scene.hpp"

namespace dipc {
namespace {

RunOptions quiet_run(int threads, int steps) {
  RunOptions options;
  options.steps = steps;
  options.write_output = false;
  options.quiet = true;
  options.report = false;
  options.host_threads = threads;
  options.partitioner = "rcb";
  return options;
}

TEST(HostThreadsRun, SameTrajectoryOnOneAndFourThreads) {
  // 28^3 = 21,952 hexes: more than 4 chunks of the loops' 4096-item grain on one rank.
  const Scene scene = parse_scene_text(
      R"({"materials": [{"name": "rubber", "E": 1e6, "nu": 0.4, "rho": 1000}],
          "geometry": [{"name": "block", "box": {"size": [1, 1, 1], "resolution": [28, 28, 28], "origin": [0, 0, 0.01]},
                        "material": "rubber"}],
          "boundary_conditions": {"gravity": [0, 0, -9.81]},
          "contact": {"enabled": true, "planes": [{"point": [0, 0, 0], "normal": [0, 0, 1]}]},
          "time": {"dt": 0.01, "steps": 1}})",
      "cube28.json", ".");
  RunResult one, four;
  ASSERT_EQ(run_scene(scene, PETSC_COMM_WORLD, quiet_run(1, 1), &one), 0);
  ASSERT_EQ(run_scene(scene, PETSC_COMM_WORLD, quiet_run(4, 1), &four), 0);
  ASSERT_TRUE(one.failure.empty()) << one.failure;
  ASSERT_TRUE(four.failure.empty()) << four.failure;
  int rank;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  if (rank == 0) {
    ASSERT_EQ(one.positions.size(), 3u * 29 * 29 * 29);
    EXPECT_TRUE(one.positions == four.positions) << "the positions differ between 1 and 4 host threads";
    EXPECT_TRUE(one.velocities == four.velocities);
  }
  EXPECT_EQ(one.newton_iterations, four.newton_iterations);
}

// PETSc's message of the error a run returns (the first, where it was raised).
PetscErrorCode keep_message(MPI_Comm, int, const char*, const char*, PetscErrorCode, PetscErrorType type,
                            const char* message, void* context) {
  auto* kept = static_cast<std::string*>(context);
  if (type == PETSC_ERROR_INITIAL && message) *kept = message;
  return PETSC_ERR_USER_INPUT;
}

TEST(HostThreadsRun, SameIntersectionReportOnOneAndFourThreads) {
  // A thin slab crossed by a smaller one: many surface edges (several chunks of the edge loop)
  // and crossings in more than one chunk.
  const Scene scene = parse_scene_text(
      R"({"materials": [{"name": "soft", "E": 1e5, "nu": 0.4, "rho": 1000}],
          "geometry": [{"name": "lower", "box": {"size": [1, 1, 0.1], "resolution": [40, 40, 2], "origin": [0, 0, 0]}},
                       {"name": "upper", "box": {"size": [0.6, 0.6, 0.1], "resolution": [12, 12, 2],
                                                 "origin": [0.21, 0.23, 0.04]}}],
          "time": {"dt": 0.01, "steps": 1}, "contact": {"enabled": true}})",
      "crossing_slabs.json", ".");
  std::string message[2];
  for (int k = 0; k < 2; ++k) {
    RunResult result;
    PetscPushErrorHandler(keep_message, &message[k]);
    const PetscErrorCode status = run_scene(scene, PETSC_COMM_WORLD, quiet_run(k == 0 ? 1 : 4, 1), &result);
    PetscPopErrorHandler();
    EXPECT_NE(status, 0);
  }
  EXPECT_NE(message[0].find("edge-triangle crossing(s), e.g. edge"), std::string::npos) << "[" << message[0] << "]";
  EXPECT_EQ(message[0], message[1]);
}

}  // namespace
}  // namespace dipc
