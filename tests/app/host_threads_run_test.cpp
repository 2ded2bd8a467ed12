// The partition's and the setup's host loops (threads/host_threads.hpp) on 1 and on 4 threads,
// through whole runs on 1 and 2 ranks: the same trajectory bit for bit (a cube resting on the
// contact plane: face matching, lumped masses, the contact surface and the start's intersection
// check all take several chunks), and the same report of an intersecting start (the first
// crossing and their count). The automatic count shares each rank's cores among the node's
// ranks bound to them; -dipc_host_threads overrides it on every rank.
#include <gtest/gtest.h>

#include <string>

#include "app/openmp_threads.hpp"
#include "app/simulation.hpp"
#include "colliding_blocks_scene.hpp"
#include "io/scene.hpp"
#include "threads/host_threads.hpp"

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

// Runs the scene for `steps` on 1 and on 4 host threads and expects the same trajectory bit for
// bit and the same Newton iterations; *one is the 1-thread run.
void expect_same_run_on_one_and_four_threads(const Scene& scene, int steps, RunResult* one) {
  RunResult four;
  ASSERT_EQ(run_scene(scene, PETSC_COMM_WORLD, quiet_run(1, steps), one), 0);
  ASSERT_EQ(run_scene(scene, PETSC_COMM_WORLD, quiet_run(4, steps), &four), 0);
  ASSERT_TRUE(one->failure.empty()) << one->failure;
  ASSERT_TRUE(four.failure.empty()) << four.failure;
  int rank;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  if (rank == 0) {
    EXPECT_TRUE(one->positions == four.positions) << "the positions differ between 1 and 4 host threads";
    EXPECT_TRUE(one->velocities == four.velocities);
  }
  EXPECT_EQ(one->newton_iterations, four.newton_iterations);
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
  RunResult one;
  expect_same_run_on_one_and_four_threads(scene, 1, &one);
  int rank;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  if (rank == 0) {
    EXPECT_EQ(one.positions.size(), 3u * 29 * 29 * 29);
  }
}

TEST(HostThreadsRun, SameContactAndFrictionTrajectoryOnOneAndFourThreads) {
  // Two blocks falling onto each other and the plane with friction: the active-set pass over the
  // candidates, the reserve of the contact and friction blocks (split by row node) and their
  // map onto the matrix all run on the host threads.
  const Scene scene = colliding_blocks_scene(14, 3);
  RunResult one;
  expect_same_run_on_one_and_four_threads(scene, 3, &one);
  EXPECT_GT(one.max_contact_pairs, 0) << "the blocks never touched: the test does not exercise contact";
  EXPECT_GT(one.new_matrix_patterns, 0) << "the active set never changed";
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

// A byte mask of CPUs [first, first + count).
std::vector<unsigned char> cpus(int first, int count) {
  std::vector<unsigned char> mask(16, 0);
  for (int c = first; c < first + count; ++c)
    mask[static_cast<std::size_t>(c / 8)] |= static_cast<unsigned char>(1u << (c % 8));
  return mask;
}

TEST(HostThreadsChoice, CoresAreSharedByTheRanksBoundToThem) {
  // mpirun -n 1 (bound to one core): one thread.
  EXPECT_EQ(share_of_affinity(cpus(0, 1), {cpus(0, 1)}).threads, 1);
  // One rank per GPU with 16 cores each (--map-by slot:PE=16): 16 threads each.
  const auto a = cpus(0, 16), b = cpus(16, 16), c = cpus(32, 16), d = cpus(48, 16);
  EXPECT_EQ(share_of_affinity(b, {a, b, c, d}).threads, 16);
  // Two ranks bound to each 32-core socket (Open MPI's socket binding for more than 2 ranks).
  const auto s0 = cpus(0, 32), s1 = cpus(32, 32);
  const AffinityShare socket = share_of_affinity(s1, {s0, s0, s1, s1});
  EXPECT_EQ(socket.cores, 32);
  EXPECT_EQ(socket.sharing, 2);
  EXPECT_EQ(socket.threads, 16);
  // Unbound ranks: the node's cores shared by all; more ranks than cores still get one.
  EXPECT_EQ(share_of_affinity(cpus(0, 64), {cpus(0, 64), cpus(0, 64), cpus(0, 64)}).threads, 21);
  EXPECT_EQ(share_of_affinity(cpus(0, 2), {cpus(0, 2), cpus(0, 2), cpus(0, 2)}).threads, 1);
}

TEST(HostThreadsChoice, RequestedCountWins) {
  OpenMpThreads openmp;
  const HostThreads chosen = choose_host_threads(PETSC_COMM_WORLD, 3, openmp);
  if (host_threads_available()) {
    EXPECT_EQ(chosen.threads, 3);
    EXPECT_EQ(chosen.why, "-dipc_host_threads");
    EXPECT_EQ(host_threads(), 3);
  }
  set_host_threads(1);
}

}  // namespace
}  // namespace dipc
