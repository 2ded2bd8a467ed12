// Hand-made point-triangle CCD cases with known impact times (src/contact/ccd/
// time_of_impact.hpp): a point tunnelling through a face in one step, triangles moving onto
// points, coplanar motion, grazing, zero and rigid motion, min_separation > 0, a step cut at
// its impact time and re-run, the iteration guard, and uniform scaling from 1e-4 to 1e4.
#include <gtest/gtest.h>

#include <cmath>

#include "ccd_test_support.hpp"

namespace {

using namespace dipc::test;
using dipc::contact::point_triangle_time_of_impact;
namespace defaults = dipc::contact::ccd_defaults;

constexpr PairKind kPT = PairKind::point_triangle;
const Vec3 T0{0, 0, 0}, T1{1, 0, 0}, T2{0, 1, 0};

Stack at(const Vec3& p, const Vec3& t0 = T0, const Vec3& t1 = T1, const Vec3& t2 = T2) { return stack(p, t0, t1, t2); }

// t* for a gap that closes at a constant rate and first reaches xi at tau.
void expect_linear_approach_bounds(const Stack& a, const Stack& b, double xi, double tau) {
  const double toi = run_ccd(kPT, a, b, xi).toi;
  EXPECT_LE(toi, tau);
  EXPECT_GE(toi, linear_approach_lower_bound() * tau * (1 - 1e-12));
  EXPECT_TRUE(collision_free_until(kPT, a, b, xi, toi));
}

TEST(PointTriangleCcd, PointTunnelsThroughFaceInOneStep) {
  // Moves 10 units through a face 1 unit away: discrete checks at t = 0, 1 see no contact.
  expect_linear_approach_bounds(at({0.25, 0.25, 1}), at({0.25, 0.25, -9}), 0.0, 0.1);
  // Oblique: hits the face interior at (0.21, 0.21, 0) at t = 0.1.
  expect_linear_approach_bounds(at({0.2, 0.2, 1}), at({0.3, 0.3, -9}), 0.0, 0.1);
}

TEST(PointTriangleCcd, PublicSignatureMatchesStackedForm) {
  const Vec3 p0{0.25, 0.25, 1}, p1{0.25, 0.25, -9};
  const double toi = point_triangle_time_of_impact(p0.data(), T0.data(), T1.data(), T2.data(), p1.data(), T0.data(),
                                                   T1.data(), T2.data(), 0.0, 1.0);
  EXPECT_EQ(toi, run_ccd(kPT, at(p0), at(p1), 0.0).toi);
  EXPECT_LT(toi, 0.1);
}

TEST(PointTriangleCcd, TriangleMovesOntoPoint) {
  const Vec3 t0b{0, 0, 2}, t1b{1, 0, 2}, t2b{0, 1, 2};
  expect_linear_approach_bounds(at({0.25, 0.25, 1}), at({0.25, 0.25, 1}, t0b, t1b, t2b), 0.0, 0.5);
  // Point and triangle both moving, the triangle also shrinking (vertices move differently):
  // checked against the first time dense sampling finds the distance <= xi = 1e-3.
  const Stack a = at({0.3, 0.2, 1.5}, {-1, -1, 0}, {2, -1, 0}, {-1, 2, 0});
  const Stack b = at({0.2, 0.3, -0.5}, {-0.5, -0.5, 0.6}, {1.0, -0.4, 0.4}, {-0.3, 1.2, 0.8});
  const double xi = 1e-3;
  const double tau = first_sampled_contact(kPT, a, b, xi, 0.0, 1.0, 200000);
  ASSERT_LT(tau, 1.0);
  const double toi = run_ccd(kPT, a, b, xi).toi;
  EXPECT_LE(toi, tau);
  EXPECT_GE(toi, 0.5 * tau);
  EXPECT_TRUE(collision_free_until(kPT, a, b, xi, toi));
}

TEST(PointTriangleCcd, CoplanarPointMovesTowardsEdge) {
  // In the triangle's plane, towards edge x = 0 (closest point inside that edge): t = 0.5.
  expect_linear_approach_bounds(at({-1, 0.25, 0}), at({1, 0.25, 0}), 0.0, 0.5);
  // Towards a vertex, in the plane: reaches t1 = (1, 0, 0) at t = 0.5.
  expect_linear_approach_bounds(at({2, 0, 0}), at({0, 0, 0}), 0.0, 0.5);
}

TEST(PointTriangleCcd, CoplanarSlidingAlongEdgeNeverTouches) {
  // At distance 0.1 from edge t0-t1 and moving parallel to it, then past vertex t1.
  const Stack a = at({0.2, -0.1, 0}), b = at({1.7, -0.1, 0});
  const auto r = run_ccd(kPT, a, b, 0.0);
  EXPECT_EQ(r.toi, 1.0);
  EXPECT_FALSE(r.truncated);
}

TEST(PointTriangleCcd, GrazingAtOneMicron) {
  // Passes 1e-6 above the plane, across the whole face: never touches (xi = 0). Additive CCD
  // stops when the gap falls below (1 - s) d0, i.e. while approaching edge x = 0, which it
  // reaches at tau = 1/3 with the distance closing at the constant rate 3 (an early t*, a
  // documented false positive, but never later than the edge).
  const Stack a = at({-1, 0.25, 1e-6}), b = at({2, 0.25, 1e-6});
  const double toi = run_ccd(kPT, a, b, 0.0).toi;
  EXPECT_LT(toi, 1.0 / 3.0);
  EXPECT_GE(toi, linear_approach_lower_bound() * (1.0 / 3.0) * (1 - 1e-9));
  EXPECT_TRUE(collision_free_until(kPT, a, b, 0.0, toi));
  // With xi = 2e-6 it does touch (just before crossing x = 0): t* stays before that.
  const double toi_xi = run_ccd(kPT, a, b, 2e-6).toi;
  EXPECT_LT(toi_xi, 1.0 / 3.0 - 5e-7);
  EXPECT_TRUE(collision_free_until(kPT, a, b, 2e-6, toi_xi));
}

TEST(PointTriangleCcd, IterationGuardReturnsConservativeTime) {
  // Sliding 0.5 across the face at height 1e-6: about 5.6e5 certified steps of 1.8e-6.
  const Stack a = at({0.1, 0.25, 1e-6}), b = at({0.6, 0.25, 1e-6});
  const auto guarded = run_ccd(kPT, a, b, 0.0);
  EXPECT_TRUE(guarded.truncated);
  const double s = defaults::conservative_rescaling;
  EXPECT_GE(guarded.toi, defaults::max_iterations * s * (1 - s) * 1e-6 / 0.5);
  EXPECT_LT(guarded.toi, 1.0);
  EXPECT_TRUE(collision_free_until(kPT, a, b, 0.0, guarded.toi));
  const auto full = run_ccd(kPT, a, b, 0.0, 1.0, s, 2000000);
  EXPECT_FALSE(full.truncated);
  EXPECT_EQ(full.toi, 1.0);
}

TEST(PointTriangleCcd, NoRelativeMotionReturnsTMaxExactly) {
  const Stack a = at({0.25, 0.25, 0.5});
  EXPECT_EQ(run_ccd(kPT, a, a, 0.0).toi, 1.0);
  EXPECT_EQ(run_ccd(kPT, a, a, 0.1, 0.37).toi, 0.37);
  // Rigid common translation, far larger than the gap.
  const Stack b = translated(a, {3.1, -7.3, 11.9});
  EXPECT_EQ(run_ccd(kPT, a, b, 0.0).toi, 1.0);
  // Moving apart.
  EXPECT_EQ(run_ccd(kPT, a, at({0.25, 0.25, 5}), 0.0).toi, 1.0);
}

TEST(PointTriangleCcd, ImpactAfterTMaxReturnsTMax) {
  // Impact at 0.1 of the full step; asking only up to 0.05.
  const Stack a = at({0.25, 0.25, 1}), b = at({0.25, 0.25, -9});
  EXPECT_EQ(run_ccd(kPT, a, b, 0.0, 0.05).toi, 0.05);
}

TEST(PointTriangleCcd, StartingInContactReturnsZero) {
  EXPECT_EQ(run_ccd(kPT, at({0.25, 0.25, 0}), at({0.25, 0.25, 1}), 0.0).toi, 0.0);
  EXPECT_EQ(run_ccd(kPT, at({0.25, 0.25, 0.05}), at({0.25, 0.25, 1}), 0.1).toi, 0.0);
}

TEST(PointTriangleCcd, MinSeparation) {
  // Gap 1 - 0.2 closed at rate 10: reaches xi = 0.2 at t = 0.08.
  expect_linear_approach_bounds(at({0.25, 0.25, 1}), at({0.25, 0.25, -9}), 0.2, 0.08);
  // Coplanar, towards edge x = 0 from x = -1 at rate 2 with xi = 0.5: t = 0.25.
  expect_linear_approach_bounds(at({-1, 0.25, 0}), at({1, 0.25, 0}), 0.5, 0.25);
}

TEST(PointTriangleCcd, DegenerateTriangleActsAsSegment) {
  // Collinear vertices along x; the point falls onto the segment at t = 0.5.
  const Vec3 c0{0, 0, 0}, c1{1, 0, 0}, c2{2, 0, 0};
  expect_linear_approach_bounds(at({1.5, 1, 0}, c0, c1, c2), at({1.5, -1, 0}, c0, c1, c2), 0.0, 0.5);
}

TEST(PointTriangleCcd, CutStepDoesNotCollapse) {
  // The line search moves to 0.8 t* and the CCD is run again over the rest of the step:
  // every re-run must still move a fixed fraction of the remaining way to the impact.
  const Stack a = at({0.25, 0.25, 1}), b = at({0.25, 0.25, -9});
  const double tau = 0.1;
  Stack current = a;
  double reached = 0.0;  // time reached on the original step
  for (int round = 0; round < 15; ++round) {
    const double remaining = (tau - reached) / (1.0 - reached);
    const double toi = run_ccd(kPT, current, b, 0.0).toi;
    ASSERT_GT(toi, 0.0) << "round " << round;
    EXPECT_LE(toi, remaining) << "round " << round;
    EXPECT_GE(toi, linear_approach_lower_bound() * remaining * (1 - 1e-9)) << "round " << round;
    current = lerp(current, b, 0.8 * toi);
    reached += 0.8 * toi * (1.0 - reached);
  }
  EXPECT_LT(reached, tau);
  EXPECT_GT(reached, tau * (1 - 1e-4));
  EXPECT_GT(pair_distance(kPT, current), 0.0);
}

TEST(PointTriangleCcd, UniformScalingGivesSameTime) {
  struct Case {
    Stack a, b;
    double xi;
  };
  const Case cases[] = {
      {at({0.2, 0.2, 1}), at({0.3, 0.3, -9}), 0.0},
      {at({0.25, 0.25, 1}), at({0.25, 0.25, -9}), 0.2},
      {at({-1, 0.25, 0}), at({1, 0.25, 0}), 0.0},
      {at({-1, 0.25, 1e-6}), at({2, 0.25, 1e-6}), 0.0},
      {at({0.3, 0.2, 1.5}, {-1, -1, 0}, {2, -1, 0}, {-1, 2, 0}),
       at({0.2, 0.3, -0.5}, {-0.5, -0.5, 0.6}, {1.0, -0.4, 0.4}, {-0.3, 1.2, 0.8}), 0.01},
  };
  for (const Case& c : cases) {
    const double reference = run_ccd(kPT, c.a, c.b, c.xi).toi;
    ASSERT_LT(reference, 1.0);
    for (int k = -4; k <= 4; ++k) {
      const double f = std::pow(10.0, k);
      const double toi = run_ccd(kPT, scaled(c.a, f), scaled(c.b, f), c.xi * f).toi;
      EXPECT_NEAR(toi, reference, 1e-9 * reference) << "scale 1e" << k;
    }
  }
}

}  // namespace
