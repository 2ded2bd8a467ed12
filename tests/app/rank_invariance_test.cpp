// Rank invariance: the beam scene (a clamped beam swinging under gravity) run on all ranks
// of the test's communicator and on rank 0 alone must give the same trajectory: relative
// difference of the displacements ≤ 1e-8 after 10 steps, with tight solver tolerances. The same
// beam of nearly incompressible mean-dilatation elements (the mixed u-p linear solve)
// must agree to 1e-6. Both partitioners (METIS, PT-Scotch) are used for the parallel run. Two
// beams side by side, one neo-Hookean and one stable neo-Hookean (materials[].model per body),
// must agree to 1e-8 too. The mixed solve at loose tolerances must end Newton where CG does.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "app/simulation.hpp"
#include "partition/slice_partition.hpp"

namespace dipc {
namespace {

std::vector<double> displacement(const std::vector<double>& x, const std::vector<double>& x0) {
  std::vector<double> u(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) u[i] = x[i] - x0[i];
  return u;
}

void beam_matches_one_rank(const Scene& scene, int steps, double tolerance, const char* partitioner = "metis") {
  MPI_Comm world = PETSC_COMM_WORLD;
  int rank;
  MPI_Comm_rank(world, &rank);
  PetscOptionsSetValue(nullptr, "-ksp_rtol", "1e-13");
  PetscOptionsSetValue(nullptr, "-ksp_atol", "1e-50");
  PetscOptionsSetValue(nullptr, "-ksp_max_it", "5000");

  RunOptions options;
  options.steps = steps;
  options.write_output = false;
  options.quiet = true;
  options.report = false;
  options.velocity_tol = 1e-9;        // m/s; displacements per step are ~1e-3 m
  options.partitioner = partitioner;  // the parallel run's; one rank needs no partitioner

  RunResult parallel;
  ASSERT_EQ(run_scene(scene, world, options, &parallel), 0);
  ASSERT_TRUE(parallel.failure.empty()) << parallel.failure;
  ASSERT_EQ(parallel.steps_taken, steps);

  // Rank 0 alone: the serial reference.
  MPI_Comm self;
  MPI_Comm_split(world, rank == 0 ? 0 : MPI_UNDEFINED, 0, &self);
  if (rank == 0) {
    RunResult serial;
    ASSERT_EQ(run_scene(scene, self, options, &serial), 0);
    ASSERT_TRUE(serial.failure.empty()) << serial.failure;
    // Initial positions = final minus the accumulated displacement is not known here; the
    // reference configuration is the 0-step run.
    RunOptions zero = options;
    zero.setup_only = true;
    RunResult reference;
    ASSERT_EQ(run_scene(scene, self, zero, &reference), 0);
    const auto up = displacement(parallel.positions, reference.positions);
    const auto us = displacement(serial.positions, reference.positions);
    ASSERT_EQ(up.size(), us.size());
    double diff = 0, norm = 0;
    for (std::size_t i = 0; i < up.size(); ++i) {
      diff = std::max(diff, std::abs(up[i] - us[i]));
      norm = std::max(norm, std::abs(us[i]));
    }
    int size;
    MPI_Comm_size(world, &size);
    std::printf("%s, ranks %d vs 1: max |u_N - u_1| = %.3e, max |u_1| = %.3e, relative %.3e\n", partitioner, size, diff,
                norm, diff / norm);
    EXPECT_GT(norm, 1e-3) << "the beam did not move: the comparison would be vacuous";
    EXPECT_LE(diff / norm, tolerance);
    MPI_Comm_free(&self);
  }
  for (const char* o : {"-ksp_rtol", "-ksp_atol", "-ksp_max_it"}) PetscOptionsClearValue(nullptr, o);
}

TEST(RankInvariance, BeamSceneTenStepsMatchesOneRank) { beam_matches_one_rank(beam_scene(), 10, 1e-8); }

// PT-Scotch cuts the beam elsewhere than METIS; the trajectory must not notice.
TEST(RankInvariance, BeamScenePtScotchMatchesOneRank) {
  if (!ptscotch_available()) GTEST_SKIP() << "this PETSc has no PT-Scotch";
  beam_matches_one_rank(beam_scene(), 10, 1e-8, "ptscotch");
}

// RCB cuts the beam across its length by centroid; the trajectory must not notice either.
TEST(RankInvariance, BeamSceneRcbMatchesOneRank) { beam_matches_one_rank(beam_scene(), 10, 1e-8, "rcb"); }

TEST(RankInvariance, MeanDilatationBeamMatchesOneRank) {
  Scene scene = beam_scene();
  for (Material& m : scene.materials) m.mean_dilatation = true, m.nu = 0.499;
  PetscOptionsSetValue(nullptr, "-dipc_mixed_solve", "1");  // below its default's lambda/mu
  beam_matches_one_rank(scene, 3, 1e-6);
  PetscOptionsClearValue(nullptr, "-dipc_mixed_solve");
}

// The mixed solve at the default preset's loose tolerances (-ksp_rtol 1e-3, velocity_tol_rel
// 1e-5) must end Newton where CG on the full Hessian does: a static clamped beam of nearly
// incompressible mean-dilatation elements (bench/locking.py's 10x1x1 at nu = 0.4999), whose
// bending modes are soft. FGMRES, which stops on the unpreconditioned residual, ended 0.65 %
// short of the deflection here (1 rank; the step failed on 2) when it was given -ksp_rtol as
// it is; at -ksp_rtol x kUnpreconditionedRtolFactor (0.01) it agrees to 6e-6 with a tight
// solve, CG to 7e-6 and MINRES to 6e-5.
// The reference is the same mixed solve at -ksp_rtol 1e-10 (its du equals the primal du,
// *MixedSolve* tests): CG on the full Hessian fails this static step on 4 ranks, at loose and
// at tight tolerances alike (found while merging, not yet investigated). Run on every rank of
// the test's communicator.
double static_beam_tip(const char* mixed_solve, const char* ksp_rtol) {
  const Scene scene = parse_scene_text(R"({
    "materials": [{"name": "m", "E": 1e8, "nu": 0.4999, "rho": 1000, "volumetric": "mean_dilatation"}],
    "geometry": [{"name": "beam", "box": {"size": [1, 0.1, 0.1], "resolution": [10, 1, 1], "origin": [0, 0, 0]},
                  "material": "m"}],
    "boundary_conditions": {"gravity": [0, 0, -9.81], "dirichlet": [{"selection": "beam.xmin", "type": "fixed"}]},
    "time": {"integrator": "static", "dt": 1, "steps": 1}})",
                                       "<static beam>", "");
  PetscOptionsSetValue(nullptr, "-ksp_rtol", ksp_rtol);
  PetscOptionsSetValue(nullptr, "-dipc_mixed_solve", mixed_solve);
  RunOptions options;
  options.write_output = false;
  options.quiet = true;
  options.report = false;
  options.velocity_tol_rel = 1e-5;
  RunResult result, reference;
  EXPECT_EQ(run_scene(scene, PETSC_COMM_WORLD, options, &result), 0);
  EXPECT_TRUE(result.failure.empty()) << result.failure;
  RunOptions zero = options;
  zero.setup_only = true;
  EXPECT_EQ(run_scene(scene, PETSC_COMM_WORLD, zero, &reference), 0);
  for (const char* o : {"-ksp_rtol", "-dipc_mixed_solve"}) PetscOptionsClearValue(nullptr, o);
  // The largest downward displacement over this rank's nodes, then over the ranks.
  double tip = 0;
  for (std::size_t i = 2; i < result.positions.size(); i += 3)
    tip = std::max(tip, reference.positions[i] - result.positions[i]);
  MPI_Allreduce(MPI_IN_PLACE, &tip, 1, MPI_DOUBLE, MPI_MAX, PETSC_COMM_WORLD);
  return tip;
}

TEST(RankInvariance, MixedSolveAtLooseToleranceEndsWhereATightSolveDoes) {
  const double loose = static_beam_tip("1", "1e-3"), tight = static_beam_tip("1", "1e-10");
  EXPECT_GT(tight, 1e-3) << "the beam did not bend: the comparison would be vacuous";
  EXPECT_LT(std::abs(loose - tight) / tight, 1e-4) << "loose " << loose << " m, tight " << tight << " m";
}

// Two clamped beams 0.3 m apart (no contact), the first neo-Hookean, the second of `model`.
Scene two_beams_scene(const std::string& model) {
  return parse_scene_text(R"({
    "materials": [{"name": "nh", "E": 1e6, "nu": 0.45, "rho": 1000},
                  {"name": "other", "E": 1e6, "nu": 0.45, "rho": 1000, "model": ")" +
                              model + R"("}],
    "geometry": [
      {"name": "a", "box": {"size": [1.0, 0.1, 0.1], "resolution": [12, 3, 3], "origin": [0, 0, 0]}, "material": "nh"},
      {"name": "b", "box": {"size": [1.0, 0.1, 0.1], "resolution": [12, 3, 3], "origin": [0, 0.3, 0]},
       "material": "other"}],
    "boundary_conditions": {"gravity": [0, 0, -9.81],
                            "dirichlet": [{"selection": "a.xmin"}, {"selection": "b.xmin"}]},
    "time": {"integrator": "implicit_euler", "dt": 0.01, "steps": 10}})",
                          "<two beams>", "");
}

TEST(RankInvariance, StableNeoHookeanBodyMatchesOneRank) {
  beam_matches_one_rank(two_beams_scene("stable_neo_hookean"), 10, 1e-8);
  // The model takes effect: on rank 0 alone, the second beam moves differently from a
  // neo-Hookean one, by far more than the 1e-8 that rank counts may change.
  int rank;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  MPI_Comm self;
  MPI_Comm_split(PETSC_COMM_WORLD, rank == 0 ? 0 : MPI_UNDEFINED, 0, &self);
  if (rank != 0) return;
  RunOptions options;
  options.steps = 10;
  options.write_output = false;
  options.quiet = true;
  options.report = false;
  options.velocity_tol = 1e-9;
  RunResult stable, plain;
  ASSERT_EQ(run_scene(two_beams_scene("stable_neo_hookean"), self, options, &stable), 0);
  ASSERT_EQ(run_scene(two_beams_scene("neo_hookean"), self, options, &plain), 0);
  ASSERT_EQ(stable.positions.size(), plain.positions.size());
  double diff = 0;
  for (std::size_t i = 0; i < plain.positions.size(); ++i)
    diff = std::max(diff, std::abs(stable.positions[i] - plain.positions[i]));
  std::printf("stable neo-Hookean vs neo-Hookean beam: max |x_s - x_n| = %.3e\n", diff);
  EXPECT_GT(diff, 1e-6);
  MPI_Comm_free(&self);
}

}  // namespace
}  // namespace dipc
