// Tests of the closest-feature classifiers (distance_types.hpp): hand-made cases for every
// point-triangle and edge-edge type, orientation independence, degenerate triangles and
// edges, parallel edges, and random configurations built inside each type's region.
#include "contact/geometry/distance_types.hpp"

#include <gtest/gtest.h>

#include <random>

#include "geometry_test_support.hpp"

namespace dipc::contact {
namespace {

using test::Stencil;
using test::Vec3;
using PT = PointTriangleType;
using EE = EdgeEdgeType;

PT classify(const Vec3& p, const Vec3& t0, const Vec3& t1, const Vec3& t2) {
  return point_triangle_distance_type(p.data(), t0.data(), t1.data(), t2.data());
}
EE classify(const Vec3& a0, const Vec3& a1, const Vec3& b0, const Vec3& b1, int) {
  return edge_edge_distance_type(a0.data(), a1.data(), b0.data(), b1.data());
}

const Vec3 O = {0, 0, 0}, X = {1, 0, 0}, Y = {0, 1, 0};

TEST(PointTriangleType, HandMadeCasesOfEveryRegion) {
  EXPECT_EQ(classify({0.25, 0.25, 1}, O, X, Y), PT::P_T);
  EXPECT_EQ(classify({0.25, 0.25, -3}, O, X, Y), PT::P_T);
  EXPECT_EQ(classify({-1, -1, 0.5}, O, X, Y), PT::P_T0);
  EXPECT_EQ(classify({2, -0.5, 0}, O, X, Y), PT::P_T1);
  EXPECT_EQ(classify({-0.5, 2, 0.3}, O, X, Y), PT::P_T2);
  EXPECT_EQ(classify({0.5, -1, 0.2}, O, X, Y), PT::P_E0);
  EXPECT_EQ(classify({1, 1, -0.3}, O, X, Y), PT::P_E1);
  EXPECT_EQ(classify({-1, 0.5, 0}, O, X, Y), PT::P_E2);
  // Obtuse triangle: beyond the obtuse vertex's edges, yet inside the long edge's slab.
  EXPECT_EQ(classify({0.5, -0.2, 0.1}, O, {1, 0, 0}, {0.5, 0.1, 0}), PT::P_E0);
  EXPECT_EQ(classify({0.5, 0.5, 0.1}, O, {1, 0, 0}, {0.5, 0.1, 0}), PT::P_T2);
}

TEST(PointTriangleType, DoesNotDependOnOrientation) {
  // Reversing the vertex order flips n; the regions (and edge names) follow the vertices.
  EXPECT_EQ(classify({0.25, 0.25, 1}, O, Y, X), PT::P_T);
  EXPECT_EQ(classify({-1, 0.5, 0}, O, Y, X), PT::P_E0);
  EXPECT_EQ(classify({0.5, -1, 0.2}, O, Y, X), PT::P_E2);
  EXPECT_EQ(classify({2, -0.5, 0}, O, Y, X), PT::P_T2);
}

TEST(PointTriangleType, DegenerateTrianglesFallBackToTheClosestEdge) {
  // Collinear vertices: E0 and E2 both contain the foot point (0.5, 0, 0).
  const PT collinear = classify({0.5, 0.3, 0.1}, O, X, {2, 0, 0});
  EXPECT_TRUE(collinear == PT::P_E0 || collinear == PT::P_E2) << int(collinear);
  EXPECT_EQ(classify({3, 0.3, 0.1}, O, X, {2, 0, 0}), PT::P_T2);
  // Two coincident vertices: the nearest vertex is t1 = t2.
  const PT coincident = classify({2, 1, 0}, O, X, X);
  EXPECT_TRUE(coincident == PT::P_T1 || coincident == PT::P_T2) << int(coincident);
  // All three coincident.
  EXPECT_EQ(classify({2, 1, 0}, X, X, X), PT::P_T0);
  // A sliver of relative height 1e-12 under a point above it: an edge or the apex, whose
  // distances differ from the face's by ~1e-12, never the ill-conditioned face itself.
  EXPECT_NE(classify({0.25, 0.3, 0.2}, O, X, {0.5, 1e-12, 0}), PT::P_T);
  EXPECT_NE(classify({0.25, 0.0, 0.2}, O, X, {0.5, 1e-12, 0}), PT::P_T);
  EXPECT_EQ(classify({0.25, -0.3, 0.2}, O, X, {0.5, 1e-12, 0}), PT::P_E0);
}

TEST(PointTriangleType, RandomConfigurationsInsideEachRegion) {
  std::mt19937_64 rng(11);
  for (int type = 0; type < 7; ++type)
    for (int k = 0; k < 200; ++k) {
      const double height = (k % 4 == 0) ? 0.0 : test::uniform(rng, -1.0, 1.0);
      const Stencil s = test::point_triangle_of_type(rng, type, height);
      ASSERT_EQ(static_cast<int>(point_triangle_distance_type(s[0], s[1], s[2], s[3])), type)
          << "sample " << k << " height " << height;
    }
}

TEST(EdgeEdgeType, HandMadeCasesOfEveryType) {
  EXPECT_EQ(classify(O, X, {0.5, -1, 1}, {0.5, 1, 1}, 0), EE::EA_EB);
  EXPECT_EQ(classify(O, X, {-1, -1, 1}, {-1, 1, 1}, 0), EE::EA0_EB);
  EXPECT_EQ(classify(O, X, {2, -1, 1}, {2, 1, 1}, 0), EE::EA1_EB);
  EXPECT_EQ(classify(O, X, {0.5, 0.5, 1}, {0.5, 2, 1}, 0), EE::EA_EB0);
  EXPECT_EQ(classify(O, X, {0.5, 2, 1}, {0.5, 0.5, 1}, 0), EE::EA_EB1);
  EXPECT_EQ(classify(O, X, {-1, 1, 0}, {-2, 2, 0}, 0), EE::EA0_EB0);
  EXPECT_EQ(classify(O, X, {-2, 2, 0}, {-1, 1, 0}, 0), EE::EA0_EB1);
  EXPECT_EQ(classify(O, X, {2, 1, 0}, {3, 2, 0}, 0), EE::EA1_EB0);
  EXPECT_EQ(classify(O, X, {3, 2, 0}, {2, 1, 0}, 0), EE::EA1_EB1);
  // Crossing edges (distance 0) and a "T" (an endpoint touching the other edge).
  EXPECT_EQ(classify(O, X, {0.5, -1, 0}, {0.5, 1, 0}, 0), EE::EA_EB);
  EXPECT_EQ(classify(O, X, {0.5, 0, 0}, {0.5, 1, 0}, 0), EE::EA_EB0);
}

TEST(EdgeEdgeType, ParallelEdgesNeverUseTheLineLineCase) {
  // Overlapping parallel edges, same and opposite direction, and collinear ones.
  const Vec3 cases[][2] = {{{0.5, 1, 0}, {1.5, 1, 0}},  {{1.5, 1, 0}, {0.5, 1, 0}}, {{0.2, 0, 1}, {0.7, 0, 1}},
                           {{-0.5, 0, 0}, {0.5, 0, 0}}, {{2, 0, 0}, {3, 0, 0}},     {{-3, 1, 1}, {-2, 1, 1}}};
  for (const auto& b : cases) {
    const EE type = classify(O, X, b[0], b[1], 0);
    EXPECT_NE(type, EE::EA_EB) << b[0][0] << " " << b[1][0];
  }
  EXPECT_EQ(classify(O, X, {2, 0, 0}, {3, 0, 0}, 0), EE::EA1_EB0);
  EXPECT_EQ(classify(O, X, {-3, 1, 1}, {-2, 1, 1}, 0), EE::EA0_EB1);
  // Nearly parallel below the threshold (sin^2 = 1e-24) behaves like parallel.
  EXPECT_NE(classify(O, X, {0.2, 0.5, 0.3}, {0.7, 0.5 + 0.5e-12, 0.3}, 0), EE::EA_EB);
}

TEST(EdgeEdgeType, ZeroLengthEdgesReduceToPointSegment) {
  EXPECT_EQ(classify(O, O, X, X, 0), EE::EA0_EB0);
  EXPECT_EQ(classify({0.5, 1, 0}, {0.5, 1, 0}, O, X, 0), EE::EA0_EB);
  EXPECT_EQ(classify({2, 1, 0}, {2, 1, 0}, O, X, 0), EE::EA0_EB1);
  EXPECT_EQ(classify(O, X, {0.5, 1, 0}, {0.5, 1, 0}, 0), EE::EA_EB0);
  EXPECT_EQ(classify(O, X, {-1, 1, 0}, {-1, 1, 0}, 0), EE::EA0_EB0);
}

TEST(EdgeEdgeType, NearlyZeroLengthEdgesReduceToPointCases) {
  // A of length 1e-14 (its direction is rounding noise) above the middle of B: ea0 to B's
  // interior, never a line through A.
  const Vec3 a0 = {0.4, 0.3, 1.0}, a1 = {0.4 + 1e-14, 0.3, 1.0 - 1e-14};
  EXPECT_EQ(classify(a0, a1, {0, 0.3, 0}, {1, 0.3, 0}, 0), EE::EA0_EB);
  EXPECT_EQ(classify({0, 0.3, 0}, {1, 0.3, 0}, a0, a1, 0), EE::EA_EB0);
  // Triangle with t2 within 1e-14 of t1: the point is nearest to that vertex, not to the
  // "edge" t1t2 whose direction is noise.
  const PT t = classify({2, 1, 0.5}, O, X, {1 + 1e-14, 1e-14, 0});
  EXPECT_TRUE(t == PT::P_T1 || t == PT::P_T2) << int(t);
}

TEST(EdgeEdgeType, RandomConfigurationsOfEachType) {
  std::mt19937_64 rng(12);
  for (int type = 0; type < 9; ++type)
    for (int k = 0; k < 200; ++k) {
      // Touching edges (separation 0) have a unique type only when both closest points are
      // interior (crossing edges); an endpoint touching is shared by neighbouring types.
      const bool touching = type == static_cast<int>(EE::EA_EB) && k % 4 == 0;
      const double separation = touching ? 0.0 : test::uniform(rng, 0.01, 1.0);
      const int* f = test::kEdgeEdgeFeatures[type];
      const Stencil s = test::edge_edge_of_features(rng, f[0], f[1], separation);
      ASSERT_EQ(static_cast<int>(edge_edge_distance_type(s[0], s[1], s[2], s[3])), type)
          << "sample " << k << " separation " << separation;
    }
}

}  // namespace
}  // namespace dipc::contact
