// Tests of the edge-edge mollifier (edge_edge_mollifier.hpp): eps_x from rest lengths,
// the value against the definition on both sides of eps_x, C1 continuity at eps_x, and
// central finite differences of c = |u x v|^2 and of m (value -> gradient -> Hessian) on
// both sides of eps_x over length scales 1e-4..1e4.
#include "contact/geometry/edge_edge_mollifier.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

#include "geometry_test_support.hpp"

namespace dipc::contact {
namespace {

using test::Stencil;
using test::Vec3;
using test::operator+;
using test::operator-;
using test::operator*;

const double kScales[] = {1e-4, 1e-2, 1.0, 1e2, 1e4};

// Two edges of lengths la, lb (times L) at angle theta with sin^2 theta = 1e-3 ratio, so
// that c / eps_x = ratio when the rest state is this state.
Stencil edges_at_ratio(std::mt19937_64& rng, double ratio, double L) {
  const Vec3 u = test::random_unit(rng);
  const Vec3 w = test::random_orthogonal_unit(rng, u);
  const double s = std::sqrt(1e-3 * ratio);
  const Vec3 v = std::sqrt(1.0 - s * s) * u + s * w;
  const double la = test::uniform(rng, 0.5, 2.0), lb = test::uniform(rng, 0.5, 2.0);
  const Vec3 a0 = {test::uniform(rng, -1, 1), test::uniform(rng, -1, 1), test::uniform(rng, -1, 1)};
  const Vec3 b0 = a0 + test::uniform(rng, 0.1, 1.0) * test::random_unit(rng);
  return Stencil{{a0, a0 + la * u, b0, b0 + lb * v}}.scaled(L, {L, 2 * L, -L});
}

double threshold_of(const Stencil& rest) { return edge_edge_mollifier_threshold(rest[0], rest[1], rest[2], rest[3]); }

TEST(EdgeEdgeMollifier, ThresholdFromRestLengths) {
  const double a0[3] = {1, 1, 1}, a1[3] = {3, 1, 1}, b0[3] = {0, 0, 0}, b1[3] = {0, 0, 3};
  EXPECT_DOUBLE_EQ(edge_edge_mollifier_threshold(a0, a1, b0, b1), 1e-3 * 4.0 * 9.0);
}

TEST(EdgeEdgeMollifier, ValueFollowsTheDefinitionOnBothSides) {
  std::mt19937_64 rng(51);
  for (double L : kScales)
    for (double ratio : {1e-4, 0.01, 0.3, 0.9, 0.999, 1.001, 1.1, 3.0, 100.0}) {
      const Stencil s = edges_at_ratio(rng, ratio, L);
      const double eps_x = threshold_of(s);
      const Vec3 n = test::cross(s.x[1] - s.x[0], s.x[3] - s.x[2]);
      const double c = test::dot(n, n);
      EXPECT_NEAR(c / eps_x, ratio, 1e-6 * ratio);
      EXPECT_NEAR(edge_edge_cross_squared_norm(s[0], s[1], s[2], s[3]), c, 1e-12 * c);
      const double expected = c < eps_x ? -c * c / (eps_x * eps_x) + 2.0 * c / eps_x : 1.0;
      EXPECT_NEAR(edge_edge_mollifier(s[0], s[1], s[2], s[3], eps_x), expected, 1e-12) << "ratio " << ratio;
    }
}

TEST(EdgeEdgeMollifier, ContinuousWithZeroSlopeAtThreshold) {
  for (double eps_x : {1e-12, 1e-3, 1.0, 1e9}) {
    EXPECT_EQ(mollifier(eps_x, eps_x), 1.0);
    EXPECT_EQ(mollifier_first_derivative(eps_x, eps_x), 0.0);
    EXPECT_EQ(mollifier(0.0, eps_x), 0.0);
    EXPECT_DOUBLE_EQ(mollifier_first_derivative(0.0, eps_x), 2.0 / eps_x);
    for (double delta : {1e-2, 1e-4, 1e-6}) {
      const double c = eps_x * (1.0 - delta);
      EXPECT_NEAR(mollifier(c, eps_x), 1.0 - delta * delta, 1e-14);
      EXPECT_NEAR(mollifier_first_derivative(c, eps_x) * eps_x, 2.0 * delta, 1e-13);
      EXPECT_DOUBLE_EQ(mollifier_second_derivative(c, eps_x) * eps_x * eps_x, -2.0);
      EXPECT_EQ(mollifier_second_derivative(eps_x * (1.0 + delta), eps_x), 0.0);
    }
  }
}

test::Derivatives cross_squared_norm_derivatives() {
  return {[](const double* x) { return edge_edge_cross_squared_norm(x, x + 3, x + 6, x + 9); },
          [](const double* x, double* g) { edge_edge_cross_squared_norm_gradient(x, x + 3, x + 6, x + 9, g); },
          [](const double* x, double* H) { edge_edge_cross_squared_norm_hessian(x, x + 3, x + 6, x + 9, H); }};
}

test::Derivatives mollifier_derivatives(double eps_x) {
  return {[=](const double* x) { return edge_edge_mollifier(x, x + 3, x + 6, x + 9, eps_x); },
          [=](const double* x, double* g) { edge_edge_mollifier_gradient(x, x + 3, x + 6, x + 9, eps_x, g); },
          [=](const double* x, double* H) { edge_edge_mollifier_hessian(x, x + 3, x + 6, x + 9, eps_x, H); }};
}

TEST(EdgeEdgeMollifier, CrossSquaredNormMatchesFiniteDifferences) {
  std::mt19937_64 rng(52);
  for (double L : kScales)
    for (int k = 0; k < 10; ++k) {
      Stencil unit;
      for (auto& v : unit.x) v = {test::uniform(rng, -1, 1), test::uniform(rng, -1, 1), test::uniform(rng, -1, 1)};
      const Stencil s = unit.scaled(L, {L, -L, 0});
      // c ~ L^4: gradient ~ L^3, Hessian ~ L^2.
      const auto x = s.flat();
      const auto e = test::finite_difference_errors(cross_squared_norm_derivatives(), x.data(), 1e-5 * L,
                                                    1e-3 * L * L * L, 1e-3 * L * L);
      EXPECT_LT(e.gradient, 1e-7) << "L " << L;
      EXPECT_LT(e.hessian, 1e-7) << "L " << L;
      EXPECT_LT(e.asymmetry, 1e-14) << "L " << L;
    }
}

TEST(EdgeEdgeMollifier, MatchesFiniteDifferencesOnBothSidesOfThreshold) {
  std::mt19937_64 rng(53);
  for (double L : kScales)
    for (double ratio : {0.01, 0.3, 0.9, 1.1, 3.0}) {
      const Stencil s = edges_at_ratio(rng, ratio, L);
      const double eps_x = threshold_of(s);
      const auto x = s.flat();
      // m is dimensionless: gradient ~ 1/L, Hessian ~ 1/L^2. The step keeps c on one side.
      const auto e = test::finite_difference_errors(mollifier_derivatives(eps_x), x.data(), 1e-6 * L, 1e-3 / L,
                                                    1e-3 / (L * L));
      EXPECT_LT(e.gradient, 1e-6) << "ratio " << ratio << " L " << L;
      EXPECT_LT(e.hessian, 1e-6) << "ratio " << ratio << " L " << L;
      EXPECT_LT(e.asymmetry, 1e-14) << "ratio " << ratio << " L " << L;
      double g[12], H[144];
      edge_edge_mollifier_gradient(s[0], s[1], s[2], s[3], eps_x, g);
      edge_edge_mollifier_hessian(s[0], s[1], s[2], s[3], eps_x, H);
      if (ratio > 1.0) {
        EXPECT_EQ(test::max_abs(g, 12), 0.0);
        EXPECT_EQ(test::max_abs(H, 144), 0.0);
      } else {
        EXPECT_GT(test::max_abs(g, 12), 1e-2 / L) << "ratio " << ratio;
      }
    }
}

}  // namespace
}  // namespace dipc::contact
