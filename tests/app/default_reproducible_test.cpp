// The default solver settings (the balanced preset, applied as the program applies it when no
// -dipc_preset is given; it keeps the AMG across Newton iterations, deciding from CG iteration
// counts) give bit-identical results when a run is repeated on the same ranks: final positions
// and velocities compared exactly, and the same Newton, CG and rebuild counts. The default
// scene has contact, friction and an impact, so the reuse rule meets new patterns and
// rebuilds. On the test's ranks (1 and 2).
#include <gtest/gtest.h>
#include <petscsys.h>

#include "app/run_options.hpp"
#include "app/simulation.hpp"
#include "app/solver_presets.hpp"
#include "io/default_scene.hpp"

namespace dipc {
namespace {

PetscErrorCode run_default(RunResult* result, std::string* preset) {
  PetscFunctionBeginUser;
  RunOptions options;
  std::vector<std::string> inserted;
  const Scene scene = default_scene();
  PetscCall(apply_solver_preset(PETSC_COMM_WORLD, preset, &inserted));
  PetscCall(read_run_options(PETSC_COMM_WORLD, scene, &options));
  options.steps = 12;  // the cube lands at step 10
  options.write_output = false;
  options.quiet = true;
  options.report = false;
  PetscCall(run_scene(scene, PETSC_COMM_WORLD, options, result));
  for (const std::string& name : inserted) PetscCall(PetscOptionsClearValue(nullptr, name.c_str()));
  PetscFunctionReturn(0);
}

TEST(DefaultSolverSettings, RepeatBitForBit) {
  RunResult first, second;
  std::string preset;
  ASSERT_EQ(run_default(&first, &preset), 0);
  ASSERT_TRUE(first.failure.empty()) << first.failure;
  EXPECT_EQ(preset, kDefaultPreset);
  ASSERT_EQ(run_default(&second, &preset), 0);
  ASSERT_TRUE(second.failure.empty()) << second.failure;
  EXPECT_GE(first.preconditioner_rebuilds, 1) << "the default keeps no preconditioner: the test checks nothing of it";
  EXPECT_EQ(second.preconditioner_rebuilds, first.preconditioner_rebuilds);
  EXPECT_EQ(second.newton_iterations, first.newton_iterations);
  EXPECT_EQ(second.linear_iterations, first.linear_iterations);
  EXPECT_EQ(second.dt_cuts, first.dt_cuts);
  int rank;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  if (rank == 0) {
    ASSERT_FALSE(first.positions.empty());
    EXPECT_TRUE(second.positions == first.positions) << "final positions differ between two identical runs";
    EXPECT_TRUE(second.velocities == first.velocities) << "final velocities differ between two identical runs";
    std::printf("default (%s): %lld Newton, %lld CG iterations, %lld AMG rebuilds; a second run %s\n", preset.c_str(),
                first.newton_iterations, first.linear_iterations, first.preconditioner_rebuilds,
                second.positions == first.positions ? "identical" : "DIFFERENT");
  }
}

}  // namespace
}  // namespace dipc
