// Triangle-mesh obstacles end to end: scenes with an OBJ obstacle written by the test, run with
// the invariants checked after every step (no inverted element, no edge–triangle crossing with
// the obstacle or between bodies, positive distance) on all ranks of the test's communicator
// and on rank 0 alone, whose final displacements must agree to 1e-6 (relative).
//  - a hex box dropped with friction into a V-shaped valley (both slopes and the valley's
//    edge and vertices meet the box);
//  - a box resting on a floor that rises along a path and lifts it (obstacle motion, CCD of the
//    obstacle's step).
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "app/simulation.hpp"
#include "displacement_difference.hpp"

namespace dipc {
namespace {

// An n × n grid of quads over [-0.4, 0.4]² at height z(x), written as OBJ quads (the reader
// splits them into triangles).
void write_floor(const std::string& path, double (*z)(double)) {
  std::ofstream out(path);
  const int n = 4;
  out << "# dipc test floor\n";
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const double x = -0.4 + 0.8 * i / n, y = -0.4 + 0.8 * j / n;
      out << "v " << x << " " << y << " " << z(x) << "\n";
    }
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int a = j * (n + 1) + i + 1;
      out << "f " << a << " " << a + 1 << " " << a + n + 2 << " " << a + n + 1 << "\n";
    }
}

std::string scene_text(const std::string& obstacle, const std::string& box_origin, const std::string& gravity,
                       double friction) {
  return R"({
    "materials": [{"name": "rubber", "E": 1e6, "nu": 0.4, "rho": 1000}],
    "geometry": [{"name": "box", "box": {"size": [0.16, 0.16, 0.16], "resolution": [3, 3, 3], "origin": )" +
         box_origin + R"(}}],
    "boundary_conditions": {"gravity": )" +
         gravity + R"(},
    "time": {"integrator": "implicit_euler", "dt": 0.005, "steps": 24},
    "contact": {"enabled": true, "dhat": 1e-3, "friction": )" +
         std::to_string(friction) + R"(,
                "obstacles": [)" +
         obstacle + R"(]}
  })";
}

// Runs the scene on every rank and on rank 0 alone; returns the displacement comparison on
// rank 0 (zeros elsewhere).
DisplacementDifference run_on_all_and_one(const Scene& scene, long* max_pairs) {
  MPI_Comm world = PETSC_COMM_WORLD;
  int rank;
  MPI_Comm_rank(world, &rank);
  PetscOptionsSetValue(nullptr, "-ksp_rtol", "1e-12");
  PetscOptionsSetValue(nullptr, "-ksp_max_it", "5000");
  RunOptions options;
  options.write_output = false;
  options.quiet = true;
  options.report = false;
  options.check_invariants = true;
  options.velocity_tol = 1e-7;
  RunResult parallel;
  EXPECT_EQ(run_scene(scene, world, options, &parallel), 0);
  EXPECT_TRUE(parallel.failure.empty()) << parallel.failure;
  *max_pairs = parallel.max_contact_pairs;
  DisplacementDifference d;
  MPI_Comm self;
  MPI_Comm_split(world, rank == 0 ? 0 : MPI_UNDEFINED, 0, &self);
  if (rank == 0) {
    RunResult serial, rest;
    EXPECT_EQ(run_scene(scene, self, options, &serial), 0);
    EXPECT_TRUE(serial.failure.empty()) << serial.failure;
    RunOptions zero = options;
    zero.setup_only = true;
    EXPECT_EQ(run_scene(scene, self, zero, &rest), 0);
    d = displacement_difference(serial, parallel, rest);
    MPI_Comm_free(&self);
  }
  for (const char* o : {"-ksp_rtol", "-ksp_max_it"}) PetscOptionsClearValue(nullptr, o);
  return d;
}

TEST(ObstacleScenes, BoxDroppedIntoAnObjValleyMatchesOneRank) {
  int rank;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  if (rank == 0) write_floor("obstacle_test_valley.obj", [](double x) { return 0.2 * std::abs(x); });
  MPI_Barrier(PETSC_COMM_WORLD);
  const Scene scene = parse_scene_text(scene_text(R"({"name": "valley", "mesh": "obstacle_test_valley.obj"})",
                                                  "[-0.05, -0.08, 0.04]", "[0, 0, -9.81]", 0.3),
                                       "valley.json", ".");
  long pairs = 0;
  const DisplacementDifference d = run_on_all_and_one(scene, &pairs);
  EXPECT_GT(pairs, 10) << "the box never reached the valley: the comparison would be vacuous";
  if (rank == 0) {
    std::printf("valley: max |u_N - u_1| = %.3e, max |u_1| = %.3e, relative %.3e\n", d.max_difference,
                d.max_displacement, d.relative());
    EXPECT_GT(d.max_displacement, 1e-2);
    EXPECT_LE(d.relative(), 1e-6);
  }
}

TEST(ObstacleScenes, FloorRisingAlongAPathLiftsTheBox) {
  int rank;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  if (rank == 0) write_floor("obstacle_test_flat.obj", [](double) { return 0.0; });
  MPI_Barrier(PETSC_COMM_WORLD);
  // No gravity: only the floor moves the box, rising 4 cm in 0.1 s, then holding.
  const Scene scene = parse_scene_text(
      scene_text(R"({"name": "lift", "mesh": "obstacle_test_flat.obj", "motion": {"type": "path", "keyframes": [
                       {"time": 0, "translation": [0, 0, 0]}, {"time": 0.1, "translation": [0.01, 0, 0.04]}]}})",
                 "[-0.08, -0.08, 0.002]", "[0, 0, 0]", 0.0),
      "lift.json", ".");
  long pairs = 0;
  const DisplacementDifference d = run_on_all_and_one(scene, &pairs);
  EXPECT_GT(pairs, 10) << "the floor never reached the box";
  if (rank == 0) {
    std::printf("lift: max |u_N - u_1| = %.3e, max |u_1| = %.3e, relative %.3e\n", d.max_difference, d.max_displacement,
                d.relative());
    EXPECT_GT(d.max_displacement, 0.03) << "the floor did not lift the box";
    EXPECT_LE(d.relative(), 1e-6);
  }
}

}  // namespace
}  // namespace dipc
