// Patch test (Irons): a homogeneous deformation x = X + A X + b imposed on the boundary of a
// distorted hex mesh must be reproduced exactly at the interior nodes. For neo-Hookean
// elasticity a constant F is an equilibrium (div P = 0), and trilinear hexes represent
// affine fields exactly, so the static solve must return it to solver precision.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "mesh/box_generator.hpp"
#include "static_problem.hpp"

namespace dipc {
namespace {

TEST(PatchTest, DistortedMeshReproducesAffineDeformation) {
  HexMesh mesh = generate_box({1, 1, 1}, {4, 3, 3}, {0, 0, 0}, 0, "cube");
  // Move every interior node by up to 20 % of the element size: the elements become
  // general (non-parallelepiped) hexahedra.
  std::vector<char> boundary(mesh.num_nodes(), 0);
  for (const char* face : {"cube.xmin", "cube.xmax", "cube.ymin", "cube.ymax", "cube.zmin", "cube.zmax"})
    for (auto n : mesh.node_sets.at(face)) boundary[n] = 1;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> shift(-0.2 / 4, 0.2 / 4);
  std::vector<std::int64_t> boundary_nodes;
  for (std::size_t n = 0; n < mesh.num_nodes(); ++n) {
    if (boundary[n]) {
      boundary_nodes.push_back(static_cast<std::int64_t>(n));
      continue;
    }
    for (int c = 0; c < 3; ++c) mesh.nodes[n][c] += shift(rng);
  }

  ProblemSetup problem;
  problem.body_materials = {{/*lambda*/ 2e5, /*mu*/ 1e5, /*rho*/ 1000}};
  problem.is_static = true;
  problem.dt = 1.0;
  problem.steps = 1;
  testing::InputDirichlet bc;
  bc.input_nodes = boundary_nodes;
  bc.motion.kind = PrescribedMotion::Kind::Affine;
  bc.motion.rate = {0.10, 0.05, 0.00, 0.02, -0.05, 0.03, 0.00, 0.04, 0.08};
  bc.motion.velocity = {0.01, -0.02, 0.03};

  testing::set_tight_solver_options();
  const std::vector<double> x = testing::solve_static(mesh, problem, {bc}, 1e-13);
  testing::clear_solver_options();

  double worst = 0;
  for (std::size_t n = 0; n < mesh.num_nodes(); ++n) {
    const auto expected = bc.motion.position(mesh.nodes[n], 1.0);
    for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(x[3 * n + c] - expected[c]));
  }
  EXPECT_LT(worst, 1e-10) << "interior nodes deviate from the imposed affine field";
}

}  // namespace
}  // namespace dipc
