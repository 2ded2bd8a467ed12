// Hand-made edge-edge CCD cases with known impact times (src/contact/ccd/time_of_impact.hpp):
// perpendicular and skew crossings, parallel and coplanar motion (sliding, approaching,
// collinear end to end), nearly parallel crossing, grazing, degenerate edges, zero and rigid
// motion, min_separation > 0, a step cut at its impact time and re-run, uniform scaling.
#include <gtest/gtest.h>

#include <cmath>

#include "ccd_test_support.hpp"

namespace {

using namespace dipc::test;
using dipc::contact::edge_edge_time_of_impact;

constexpr PairKind kEE = PairKind::edge_edge;

void expect_linear_approach_bounds(const Stack& a, const Stack& b, double xi, double tau) {
  const double toi = run_ccd(kEE, a, b, xi).toi;
  EXPECT_LE(toi, tau);
  EXPECT_GE(toi, linear_approach_lower_bound() * tau * (1 - 1e-12));
  EXPECT_TRUE(collision_free_until(kEE, a, b, xi, toi));
}

// ea along x at height 1 falling to height -1; eb along y at height 0, static.
const Stack kCrossA = stack({-1, 0, 1}, {1, 0, 1}, {0, -1, 0}, {0, 1, 0});
const Stack kCrossB = stack({-1, 0, -1}, {1, 0, -1}, {0, -1, 0}, {0, 1, 0});

TEST(EdgeEdgeCcd, PerpendicularCrossing) { expect_linear_approach_bounds(kCrossA, kCrossB, 0.0, 0.5); }

TEST(EdgeEdgeCcd, PublicSignatureMatchesStackedForm) {
  const double* a = kCrossA.data();
  const double* b = kCrossB.data();
  const double toi = edge_edge_time_of_impact(a, a + 3, a + 6, a + 9, b, b + 3, b + 6, b + 9, 0.0, 1.0);
  EXPECT_EQ(toi, run_ccd(kEE, kCrossA, kCrossB, 0.0).toi);
  EXPECT_LT(toi, 0.5);
}

TEST(EdgeEdgeCcd, SkewTranslatingEdges) {
  // Both edges translate, so n = u x v is constant and the signed distance along n,
  // h(t) = n.(a0(t) - b0(t)) / |n|, is linear: impact at tau = h0 / (h0 - h1).
  const Vec3 a0{-1, -0.5, 0.5}, a1{1, 0.5, 0.7}, b0{0.2, -1, -0.1}, b1{-0.1, 1, 0.1};
  const Vec3 da{0.3, 0.1, -2}, db{-0.2, 0.4, 0.5};
  const Stack a = stack(a0, a1, b0, b1);
  Stack b = a;
  for (int k = 0; k < 3; ++k) {
    b[k] += da[k], b[3 + k] += da[k];
    b[6 + k] += db[k], b[9 + k] += db[k];
  }
  const Vec3 u{a1[0] - a0[0], a1[1] - a0[1], a1[2] - a0[2]};
  const Vec3 v{b1[0] - b0[0], b1[1] - b0[1], b1[2] - b0[2]};
  const Vec3 n{u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
  const double nn = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  auto h = [&](double t) {
    double s = 0;
    for (int k = 0; k < 3; ++k) s += n[k] * (a0[k] + t * da[k] - b0[k] - t * db[k]);
    return s / nn;
  };
  const double tau = h(0) / (h(0) - h(1));
  ASSERT_GT(tau, 0.0);
  ASSERT_LT(tau, 1.0);
  // Premise of the bound: the closest points are interior on [0, tau], so d = |h|.
  for (int i = 0; i <= 100; ++i) {
    const double t = tau * i / 100;
    ASSERT_NEAR(distance_at(kEE, a, b, t), std::fabs(h(t)), 1e-12) << "t = " << t;
  }
  expect_linear_approach_bounds(a, b, 0.0, tau);
}

TEST(EdgeEdgeCcd, RotatingEdgesAgainstSampling) {
  const Stack a = stack({-1, 0, 1}, {1, 0, 1}, {0, -1, 0}, {0, 1, 0});
  const Stack b = stack({-1, 0.5, -0.5}, {1, -0.5, 0.3}, {0.2, -1, 0.2}, {-0.1, 1, -0.1});
  const double xi = 1e-3;  // sampling cannot hit a distance of exactly 0
  const double tau = first_sampled_contact(kEE, a, b, xi, 0.0, 1.0, 200000);
  ASSERT_LT(tau, 1.0);
  const double toi = run_ccd(kEE, a, b, xi).toi;
  EXPECT_LE(toi, tau);
  EXPECT_GE(toi, 0.5 * tau);
  EXPECT_TRUE(collision_free_until(kEE, a, b, xi, toi));
}

TEST(EdgeEdgeCcd, ParallelEdgesSlidingAlongEachOther) {
  const Stack a = stack({0, 0, 0}, {1, 0, 0}, {0, 0.1, 0}, {1, 0.1, 0});
  const Stack b = stack({0, 0, 0}, {1, 0, 0}, {3, 0.1, 0}, {4, 0.1, 0});
  const auto r = run_ccd(kEE, a, b, 0.0);
  EXPECT_EQ(r.toi, 1.0);
  EXPECT_FALSE(r.truncated);
}

TEST(EdgeEdgeCcd, ParallelEdgesApproaching) {
  const Stack a = stack({0, 0, 0}, {1, 0, 0}, {0.3, 0.5, 0}, {1.3, 0.5, 0});
  const Stack b = stack({0, 0, 0}, {1, 0, 0}, {0.3, -0.5, 0}, {1.3, -0.5, 0});
  expect_linear_approach_bounds(a, b, 0.0, 0.5);
  // Out of plane as well: eb 0.5 above ea, falling by 1.
  const Stack c = stack({0, 0, 0}, {1, 0, 0}, {0.3, 0, 0.5}, {1.3, 0, 0.5});
  const Stack d = stack({0, 0, 0}, {1, 0, 0}, {0.3, 0, -0.5}, {1.3, 0, -0.5});
  expect_linear_approach_bounds(c, d, 0.0, 0.5);
}

TEST(EdgeEdgeCcd, CoplanarMotion) {
  // eb's end reaches the interior of ea at t = 0.5.
  expect_linear_approach_bounds(stack({0, 0, 0}, {1, 0, 0}, {0.5, 1, 0}, {0.5, 2, 0}),
                                stack({0, 0, 0}, {1, 0, 0}, {0.5, -1, 0}, {0.5, 0, 0}), 0.0, 0.5);
  // Collinear, end to end: gap 1 closed at rate 2.
  expect_linear_approach_bounds(stack({0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}),
                                stack({0, 0, 0}, {1, 0, 0}, {0, 0, 0}, {1, 0, 0}), 0.0, 0.5);
}

TEST(EdgeEdgeCcd, NearlyParallelCrossing) {
  // Angle 1e-3 between the edges; they cross at the origin at t = 0.5.
  expect_linear_approach_bounds(stack({-1, 0, 1}, {1, 0, 1}, {-1, -1e-3, 0}, {1, 1e-3, 0}),
                                stack({-1, 0, -1}, {1, 0, -1}, {-1, -1e-3, 0}, {1, 1e-3, 0}), 0.0, 0.5);
}

TEST(EdgeEdgeCcd, DegenerateEdgeActsAsPoint) {
  // ea collapsed to the point (0.5, 1, 1), moving onto eb's interior at t = 0.5.
  expect_linear_approach_bounds(stack({0.5, 1, 1}, {0.5, 1, 1}, {0, 0, 0}, {1, 0, 0}),
                                stack({0.5, -1, -1}, {0.5, -1, -1}, {0, 0, 0}, {1, 0, 0}), 0.0, 0.5);
}

TEST(EdgeEdgeCcd, GrazingAtOneMicron) {
  // ea passes 1e-6 above eb, sweeping over its whole length: no contact for xi = 0. The gap
  // closes at the constant rate 4 until ea is over eb's end (t = 0.25).
  const Stack a = stack({-1, -2, 1e-6}, {1, -2, 1e-6}, {0, -1, 0}, {0, 1, 0});
  const Stack b = stack({-1, 2, 1e-6}, {1, 2, 1e-6}, {0, -1, 0}, {0, 1, 0});
  const double toi = run_ccd(kEE, a, b, 0.0).toi;
  EXPECT_LT(toi, 0.25);
  EXPECT_GE(toi, linear_approach_lower_bound() * 0.25 * (1 - 1e-9));
  EXPECT_TRUE(collision_free_until(kEE, a, b, 0.0, toi));
  const double toi_xi = run_ccd(kEE, a, b, 2e-6).toi;
  EXPECT_LT(toi_xi, 0.25 - 4e-7);
  EXPECT_TRUE(collision_free_until(kEE, a, b, 2e-6, toi_xi));
}

TEST(EdgeEdgeCcd, NoRelativeMotionReturnsTMaxExactly) {
  EXPECT_EQ(run_ccd(kEE, kCrossA, kCrossA, 0.0).toi, 1.0);
  EXPECT_EQ(run_ccd(kEE, kCrossA, kCrossA, 0.2, 0.61).toi, 0.61);
  EXPECT_EQ(run_ccd(kEE, kCrossA, translated(kCrossA, {-5.5, 2.25, 9.75}), 0.0).toi, 1.0);
  // Moving apart.
  EXPECT_EQ(run_ccd(kEE, kCrossA, stack({-1, 0, 4}, {1, 0, 4}, {0, -1, 0}, {0, 1, 0}), 0.0).toi, 1.0);
}

TEST(EdgeEdgeCcd, StartingInContactReturnsZero) {
  const Stack touching = stack({-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0});
  EXPECT_EQ(run_ccd(kEE, touching, kCrossA, 0.0).toi, 0.0);
  EXPECT_EQ(run_ccd(kEE, kCrossA, kCrossB, 1.0).toi, 0.0);
  EXPECT_EQ(run_ccd(kEE, kCrossA, kCrossB, 1.5).toi, 0.0);
}

TEST(EdgeEdgeCcd, MinSeparation) {
  // Gap 1 - 0.3 closed at rate 2.
  expect_linear_approach_bounds(kCrossA, kCrossB, 0.3, 0.35);
}

TEST(EdgeEdgeCcd, CutStepDoesNotCollapse) {
  const double tau = 0.5;
  Stack current = kCrossA;
  double reached = 0.0;
  for (int round = 0; round < 15; ++round) {
    const double remaining = (tau - reached) / (1.0 - reached);
    const double toi = run_ccd(kEE, current, kCrossB, 0.0).toi;
    ASSERT_GT(toi, 0.0) << "round " << round;
    EXPECT_LE(toi, remaining) << "round " << round;
    EXPECT_GE(toi, linear_approach_lower_bound() * remaining * (1 - 1e-9)) << "round " << round;
    current = lerp(current, kCrossB, 0.8 * toi);
    reached += 0.8 * toi * (1.0 - reached);
  }
  EXPECT_LT(reached, tau);
  EXPECT_GT(reached, tau * (1 - 1e-4));
  EXPECT_GT(pair_distance(kEE, current), 0.0);
}

TEST(EdgeEdgeCcd, UniformScalingGivesSameTime) {
  struct Case {
    Stack a, b;
    double xi;
  };
  const Case cases[] = {
      {kCrossA, kCrossB, 0.0},
      {kCrossA, kCrossB, 0.3},
      {stack({-1, 0, 1}, {1, 0, 1}, {0, -1, 0}, {0, 1, 0}),
       stack({-1, 0.5, -0.5}, {1, -0.5, 0.3}, {0.2, -1, 0.2}, {-0.1, 1, -0.1}), 0.0},
      {stack({-1, -2, 1e-6}, {1, -2, 1e-6}, {0, -1, 0}, {0, 1, 0}),
       stack({-1, 2, 1e-6}, {1, 2, 1e-6}, {0, -1, 0}, {0, 1, 0}), 0.0},
      {stack({0, 0, 0}, {1, 0, 0}, {0.5, 1, 0}, {0.5, 2, 0}), stack({0, 0, 0}, {1, 0, 0}, {0.5, -1, 0}, {0.5, 0, 0}),
       0.05},
  };
  for (const Case& c : cases) {
    const double reference = run_ccd(kEE, c.a, c.b, c.xi).toi;
    ASSERT_LT(reference, 1.0);
    for (int k = -4; k <= 4; ++k) {
      const double f = std::pow(10.0, k);
      const double toi = run_ccd(kEE, scaled(c.a, f), scaled(c.b, f), c.xi * f).toi;
      EXPECT_NEAR(toi, reference, 1e-9 * reference) << "scale 1e" << k;
    }
  }
}

}  // namespace
