// Large prescribed motions: squashing a soft cube to 40 % of its height in one static load
// step makes the first guess (interior at rest, top face moved) invert the top layer. The
// integrator must reach the prescribed positions by continuation, never accept an inverted
// state, and land on the same equilibrium as eight small load steps.
#include <gtest/gtest.h>

#include <cmath>

#include "mesh/box_generator.hpp"
#include "static_problem.hpp"

namespace dipc {
namespace {

std::vector<double> squash(int steps, StepReport* last) {
  HexMesh mesh = generate_box({1, 1, 1}, {4, 4, 4}, {0, 0, 0}, 0, "block");
  ProblemSetup problem;
  const double E = 1e5, nu = 0.45;
  problem.body_materials = {{E * nu / ((1 + nu) * (1 - 2 * nu)), E / (2 * (1 + nu)), 1000}};
  problem.is_static = true;
  problem.steps = steps;
  problem.dt = 1.0 / steps;
  testing::InputDirichlet bottom, top;
  bottom.input_nodes = mesh.node_sets.at("block.zmin");
  top.input_nodes = mesh.node_sets.at("block.zmax");
  top.motion.kind = PrescribedMotion::Kind::Velocity;
  top.motion.velocity = {0, 0, -0.6};
  return testing::solve_static(mesh, problem, {bottom, top}, 1e-11, last);
}

TEST(DirichletContinuation, OneLargeStepEqualsManySmallOnes) {
  testing::set_tight_solver_options();
  StepReport one, many;
  const std::vector<double> x1 = squash(1, &one);
  const std::vector<double> x8 = squash(8, &many);
  testing::clear_solver_options();
  EXPECT_GT(one.dirichlet_substeps, 0) << "the single step should have needed continuation";
  EXPECT_GT(one.min_volume_ratio, 0.0);
  EXPECT_LT(one.min_volume_ratio, 0.5) << "the cube was not squashed";
  double diff = 0;
  for (std::size_t i = 0; i < x1.size(); ++i) diff = std::max(diff, std::abs(x1[i] - x8[i]));
  EXPECT_LT(diff, 1e-8) << "one step with continuation and eight load steps reach different equilibria";
}

}  // namespace
}  // namespace dipc
