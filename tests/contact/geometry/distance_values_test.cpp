// Tests of the distance values (point_triangle_distance.hpp, edge_edge_distance.hpp):
// closed-form cases, the separation built into configurations of each type, and random
// configurations over length scales 1e-4..1e4 against an independent exact reference and
// a brute-force minimum over a fine barycentric sampling (never above it, and within the
// sampling resolution of it).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "contact/geometry/edge_edge_distance.hpp"
#include "contact/geometry/point_triangle_distance.hpp"
#include "geometry_test_support.hpp"

namespace dipc::contact {
namespace {

using test::Stencil;
using test::Vec3;

double pt_distance(const Stencil& s) { return point_triangle_distance(s[0], s[1], s[2], s[3]); }
double ee_distance(const Stencil& s) { return edge_edge_distance(s[0], s[1], s[2], s[3]); }

const double kScales[] = {1e-4, 1e-2, 1.0, 1e2, 1e4};

TEST(DistanceValues, ClosedFormCases) {
  const Vec3 O = {0, 0, 0}, X = {1, 0, 0}, Y = {0, 1, 0};
  EXPECT_DOUBLE_EQ(pt_distance(Stencil{{Vec3{0.25, 0.25, -0.7}, O, X, Y}}), 0.49);
  EXPECT_DOUBLE_EQ(pt_distance(Stencil{{Vec3{0.5, -2, 1}, O, X, Y}}), 5.0);                // edge E0
  EXPECT_DOUBLE_EQ(pt_distance(Stencil{{Vec3{1, 1, 0}, O, X, Y}}), 0.5);                   // edge E1
  EXPECT_DOUBLE_EQ(pt_distance(Stencil{{Vec3{-1, -2, 2}, O, X, Y}}), 9.0);                 // vertex t0
  EXPECT_DOUBLE_EQ(pt_distance(Stencil{{Vec3{0.2, 0.3, 0}, O, X, Y}}), 0.0);               // coplanar, inside
  EXPECT_DOUBLE_EQ(ee_distance(Stencil{{O, X, Vec3{0.5, -1, 3}, Vec3{0.5, 1, 3}}}), 9.0);  // line-line
  EXPECT_DOUBLE_EQ(ee_distance(Stencil{{O, X, Vec3{-1, -1, 1}, Vec3{-1, 1, 1}}}), 2.0);    // ea0-EB
  EXPECT_DOUBLE_EQ(ee_distance(Stencil{{O, X, Vec3{0.5, 2, 0}, Vec3{0.5, 3, 0}}}), 4.0);   // eb0-EA
  EXPECT_DOUBLE_EQ(ee_distance(Stencil{{O, X, Vec3{3, 0, 0}, Vec3{4, 0, 0}}}), 4.0);       // ea1-eb0
  EXPECT_DOUBLE_EQ(ee_distance(Stencil{{O, X, Vec3{0.2, 1, 1}, Vec3{0.9, 1, 1}}}), 2.0);   // parallel
}

TEST(DistanceValues, EdgeEdgeConfigurationsHaveTheirBuiltInSeparation) {
  std::mt19937_64 rng(21);
  for (double L : kScales)
    for (int type = 0; type < 9; ++type)
      for (int k = 0; k < 20; ++k) {
        const double separation = test::uniform(rng, 0.01, 1.0);
        const int* f = test::kEdgeEdgeFeatures[type];
        const Vec3 offset = {test::uniform(rng, -3, 3) * L, test::uniform(rng, -3, 3) * L, 0.0};
        const Stencil s = test::edge_edge_of_features(rng, f[0], f[1], separation).scaled(L, offset);
        const EdgeEdgeType t = edge_edge_distance_type(s[0], s[1], s[2], s[3]);
        ASSERT_EQ(static_cast<int>(t), type);
        const double expected = separation * separation * L * L;
        EXPECT_NEAR(edge_edge_distance(s[0], s[1], s[2], s[3], t), expected, 1e-11 * L * L)
            << "type " << type << " L " << L;
      }
}

// Random stencils in a cube of size L, offset by up to 3 L: every type occurs.
TEST(DistanceValues, RandomConfigurationsMatchReferenceAndBruteForce) {
  std::mt19937_64 rng(22);
  int pt_seen[7] = {}, ee_seen[9] = {};
  for (double L : kScales) {
    const Vec3 offset = {test::uniform(rng, -3, 3) * L, test::uniform(rng, -3, 3) * L, test::uniform(rng, -3, 3) * L};
    for (int k = 0; k < 300; ++k) {
      Stencil unit;
      for (auto& v : unit.x) v = {test::uniform(rng, -1, 1), test::uniform(rng, -1, 1), test::uniform(rng, -1, 1)};
      const Stencil s = unit.scaled(L, offset);
      const double tolerance = 1e-12 * L * L;

      const double d_pt = pt_distance(s);
      ++pt_seen[static_cast<int>(point_triangle_distance_type(s[0], s[1], s[2], s[3]))];
      const double ref_pt = test::reference_point_triangle(s);
      ASSERT_NEAR(d_pt, ref_pt, tolerance + 1e-10 * ref_pt) << "point-triangle sample " << k << " L " << L;

      const double d_ee = ee_distance(s);
      ++ee_seen[static_cast<int>(edge_edge_distance_type(s[0], s[1], s[2], s[3]))];
      const double ref_ee = test::reference_edge_edge(s);
      ASSERT_NEAR(d_ee, ref_ee, tolerance + 1e-10 * ref_ee) << "edge-edge sample " << k << " L " << L;

      if (k >= 30) continue;  // brute force on a subset: it costs ~1e5 evaluations each
      double spacing;
      const double brute_pt = test::brute_force_point_triangle(s, 200, &spacing);
      EXPECT_LE(d_pt, brute_pt + tolerance);
      EXPECT_LE(std::sqrt(brute_pt) - std::sqrt(d_pt), spacing);
      const double brute_ee = test::brute_force_edge_edge(s, 300, &spacing);
      EXPECT_LE(d_ee, brute_ee + tolerance);
      EXPECT_LE(std::sqrt(brute_ee) - std::sqrt(d_ee), spacing);
    }
  }
  for (int t = 0; t < 7; ++t) EXPECT_GT(pt_seen[t], 0) << "point-triangle type " << t << " never sampled";
  for (int t = 0; t < 9; ++t) EXPECT_GT(ee_seen[t], 0) << "edge-edge type " << t << " never sampled";
}

TEST(DistanceValues, InvalidTypeGivesNaN) {
  const double a[3] = {0, 0, 0}, b[3] = {1, 0, 0}, c[3] = {0, 1, 0}, d[3] = {0, 0, 1};
  EXPECT_TRUE(std::isnan(point_triangle_distance(d, a, b, c, static_cast<PointTriangleType>(7))));
  EXPECT_TRUE(std::isnan(edge_edge_distance(a, b, c, d, static_cast<EdgeEdgeType>(-1))));
}

}  // namespace
}  // namespace dipc::contact
