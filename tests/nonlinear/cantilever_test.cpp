// Verification against beam theory: a slender cantilever (L/b = 10, ν = 0) clamped at x = 0
// and loaded by its own weight deflects at the tip by w = q L⁴ / (8 E I), q = ρ g b²,
// I = b⁴/12 (Euler–Bernoulli; Timoshenko's shear term adds (E/G)(b/L)²/(3κ) ≈ 0.8 % at this
// slenderness). Fully integrated trilinear hexes are too stiff in bending (shear locking), so
// the error must fall under refinement (cubic elements, 1, 2, 4 through the thickness:
// measured 33 %, 10 %, 2.3 %) and be within a few percent on the finest mesh.
#include <gtest/gtest.h>

#include <cmath>

#include "mesh/box_generator.hpp"
#include "static_problem.hpp"

namespace dipc {
namespace {

struct Beam {
  double L = 1.0, b = 0.1, E = 1e7, rho = 1000, g = 2.0;  // tip deflection ≈ 1e-3 L: linear regime
  double euler_bernoulli_tip() const {
    const double q = rho * g * b * b, I = b * b * b * b / 12;
    return q * L * L * L * L / (8 * E * I);
  }
};

double tip_deflection(const Beam& beam, int nx, int nyz) {
  HexMesh mesh = generate_box({beam.L, beam.b, beam.b}, {nx, nyz, nyz}, {0, 0, 0}, 0, "beam");
  ProblemSetup problem;
  problem.body_materials = {{/*lambda*/ 0.0, /*mu*/ beam.E / 2, beam.rho}};  // ν = 0
  problem.gravity = {0, 0, -beam.g};
  problem.is_static = true;
  problem.dt = 1.0;
  problem.steps = 1;
  testing::InputDirichlet clamp;
  clamp.input_nodes = mesh.node_sets.at("beam.xmin");
  const std::vector<double> x = testing::solve_static(mesh, problem, {clamp}, 1e-12 * beam.L);
  // Mean vertical displacement of the tip face.
  double w = 0;
  const auto& tip = mesh.node_sets.at("beam.xmax");
  for (auto n : tip) w += mesh.nodes[n][2] - x[3 * n + 2];
  return w / static_cast<double>(tip.size());
}

TEST(Cantilever, MatchesEulerBernoulliAndConvergesUnderRefinement) {
  Beam beam;
  const double exact = beam.euler_bernoulli_tip();
  testing::set_tight_solver_options();
  std::vector<double> errors;
  for (int level : {1, 2, 4}) {
    const double w = tip_deflection(beam, 10 * level, level);
    errors.push_back(std::abs(w - exact) / exact);
    if (testing::comm_rank() == 0)
      std::printf("cantilever %2dx%dx%d: tip deflection %.6e, Euler-Bernoulli %.6e, relative error %.4f\n", 10 * level,
                  level, level, w, exact, errors.back());
  }
  testing::clear_solver_options();
  EXPECT_LT(errors[1], errors[0]);
  EXPECT_LT(errors[2], errors[1]);
  EXPECT_LT(errors[2], 0.03) << "finest mesh is not within 3 % of Euler-Bernoulli";
}

}  // namespace
}  // namespace dipc
