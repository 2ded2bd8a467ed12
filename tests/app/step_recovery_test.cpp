// Honest convergence and step recovery end to end (time_integrator.hpp, step_recovery.hpp):
// a box hitting another at 100 m/s cannot be taken in one step of 5 ms (Newton runs out of
// iterations), so the step is cut and retried, and the run ends at the scene's times with
// every step converged by dipc's own criterion. (With no room to cut, the same run must stop
// with exit status 2: input_errors_test.cpp, which starts the program as its own process.)
// Run on 1 and 2 ranks; the 2-rank run is compared with a 1-rank run of the same scene.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "app/simulation.hpp"
#include "displacement_difference.hpp"
#include "impact_scene.hpp"

namespace dipc {
namespace {

// The impact at 100 m/s, no friction: too fast for the scene's dt without cuts.
const std::string kImpact = test::impact_scene(100, 0, "step_recovery_output");

std::vector<std::vector<std::string>> read_csv(const std::string& path) {
  std::vector<std::vector<std::string>> rows;
  std::ifstream in(path);
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> cells;
    std::stringstream s(line);
    for (std::string c; std::getline(s, c, ',');) cells.push_back(c);
    rows.push_back(cells);
  }
  return rows;
}

RunOptions quiet_options(const std::string& output_dir) {
  RunOptions o;
  o.quiet = true;
  o.report = false;
  o.check_invariants = true;
  o.output_dir = output_dir;
  o.write_output = !output_dir.empty();
  return o;
}

TEST(StepRecovery, FastImpactIsTakenInCutStepsAtTheScenesTimes) {
  MPI_Comm world = PETSC_COMM_WORLD;
  int rank, size;
  MPI_Comm_rank(world, &rank);
  MPI_Comm_size(world, &size);
  const Scene scene = parse_scene_text(kImpact, "impact.json", ".");
  const std::string dir = "step_recovery_np" + std::to_string(size);
  RunResult run;
  ASSERT_EQ(run_scene(scene, world, quiet_options(dir), &run), 0);
  ASSERT_TRUE(run.failure.empty()) << run.failure;
  EXPECT_EQ(run.steps_taken, 4);
  EXPECT_GT(run.dt_cuts, 0) << "the impact no longer needs a cut: the test lost its purpose";

  if (rank == 0) {
    const auto rows = read_csv(dir + "/stats.csv");
    ASSERT_EQ(rows.size(), 5u);
    const auto& header = rows[0];
    auto column = [&](const std::string& name) {
      for (std::size_t c = 0; c < header.size(); ++c)
        if (header[c] == name) return c;
      ADD_FAILURE() << "no column " << name;
      return std::size_t{0};
    };
    double cuts = 0;
    for (std::size_t k = 1; k < rows.size(); ++k) {
      EXPECT_EQ(rows[k][column("converged_by")], "velocity") << "step " << k;
      // Times are k·dt, not a sum of (sub-)steps: printed with 10 digits they read exactly.
      char expected[32];
      std::snprintf(expected, sizeof expected, "%.10g", k * 0.005);
      EXPECT_EQ(rows[k][column("t")], expected);
      cuts += std::stod(rows[k][column("dt_cuts")]);
      EXPECT_GE(std::stod(rows[k][column("substeps")]), 1);
    }
    EXPECT_EQ(cuts, static_cast<double>(run.dt_cuts));
  }

  // The same decisions on every rank count: the 1-rank run ends where this one does.
  if (size > 1) {
    MPI_Comm self;
    MPI_Comm_split(world, rank == 0 ? 0 : MPI_UNDEFINED, 0, &self);
    if (rank == 0) {
      RunResult serial, rest;
      ASSERT_EQ(run_scene(scene, self, quiet_options(""), &serial), 0);
      ASSERT_TRUE(serial.failure.empty()) << serial.failure;
      EXPECT_EQ(serial.dt_cuts, run.dt_cuts);
      RunOptions zero = quiet_options("");
      zero.setup_only = true;
      ASSERT_EQ(run_scene(scene, self, zero, &rest), 0);
      const DisplacementDifference d = displacement_difference(serial, run, rest);
      std::printf("%d ranks vs 1 after the cut impact: relative difference %.3e\n", size, d.relative());
      EXPECT_LE(d.relative(), 1e-6);
      MPI_Comm_free(&self);
    }
  }
}

}  // namespace
}  // namespace dipc
