// Tests of the CCD's own distance helpers (src/contact/ccd/ccd_distances.hpp): hand-made
// configurations with known answers for every closest-feature case, and random
// configurations (general, coplanar, parallel, nearly parallel, degenerate) against an
// independent reference that minimises the squared distance over the primitives'
// parameters by grid search + pattern search.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <random>

#include "ccd_test_support.hpp"
#include "contact/ccd/ccd_distances.hpp"

namespace {

using dipc::contact::ccd::edge_edge_distance_squared;
using dipc::contact::ccd::point_segment_distance_squared;
using dipc::contact::ccd::point_triangle_distance_squared;
using dipc::test::Vec3;

double pt(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  return point_triangle_distance_squared(p.data(), a.data(), b.data(), c.data());
}
double ee(const Vec3& a0, const Vec3& a1, const Vec3& b0, const Vec3& b1) {
  return edge_edge_distance_squared(a0.data(), a1.data(), b0.data(), b1.data());
}

// Minimises f over the 2D parameter domain given by `feasible`: best point of a 41 x 41 grid
// on [0,1]^2, then pattern search along 8 directions (coordinate and diagonal) with step
// halving. f is a convex quadratic and the domain a triangle or square whose sides are along
// those directions, so the search converges to the minimum (Lewis and Torczon 1999).
double pattern_search_min(const std::function<double(double, double)>& f,
                          const std::function<bool(double, double)>& feasible) {
  double bx = 0.0, by = 0.0, best = f(0.0, 0.0);
  const int n = 40;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) {
      const double x = double(i) / n, y = double(j) / n;
      if (!feasible(x, y)) continue;
      const double v = f(x, y);
      if (v < best) best = v, bx = x, by = y;
    }
  const double dirs[8][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}, {1, -1}, {-1, 1}, {1, 1}, {-1, -1}};
  double h = 1.0 / n;
  for (int moves = 0; h > 1e-14 && moves < 200000; ++moves) {
    bool improved = false;
    for (const auto& d : dirs) {
      const double x = bx + h * d[0], y = by + h * d[1];
      if (!feasible(x, y)) continue;
      const double v = f(x, y);
      if (v < best) {
        best = v, bx = x, by = y, improved = true;
        break;
      }
    }
    if (!improved) h *= 0.5;
  }
  return best;
}

double sq(const Vec3& a) { return a[0] * a[0] + a[1] * a[1] + a[2] * a[2]; }

double reference_point_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  auto f = [&](double u, double v) {
    Vec3 r;
    for (int k = 0; k < 3; ++k) r[k] = p[k] - (a[k] + u * (b[k] - a[k]) + v * (c[k] - a[k]));
    return sq(r);
  };
  auto feasible = [](double u, double v) { return u >= 0 && v >= 0 && u + v <= 1; };
  return pattern_search_min(f, feasible);
}

double reference_edge_edge(const Vec3& a0, const Vec3& a1, const Vec3& b0, const Vec3& b1) {
  auto f = [&](double s, double t) {
    Vec3 r;
    for (int k = 0; k < 3; ++k) r[k] = (a0[k] + s * (a1[k] - a0[k])) - (b0[k] + t * (b1[k] - b0[k]));
    return sq(r);
  };
  auto feasible = [](double s, double t) { return s >= 0 && s <= 1 && t >= 0 && t <= 1; };
  return pattern_search_min(f, feasible);
}

TEST(CcdDistances, PointSegmentCases) {
  const Vec3 a{0, 0, 0}, b{2, 0, 0};
  const Vec3 inner{1, 1, 1}, before{-1, 1, 0}, after{4, 0, 2};
  EXPECT_DOUBLE_EQ(point_segment_distance_squared(inner.data(), a.data(), b.data()), 2.0);
  EXPECT_DOUBLE_EQ(point_segment_distance_squared(before.data(), a.data(), b.data()), 2.0);
  EXPECT_DOUBLE_EQ(point_segment_distance_squared(after.data(), a.data(), b.data()), 8.0);
  EXPECT_DOUBLE_EQ(point_segment_distance_squared(inner.data(), a.data(), a.data()), 3.0);
}

TEST(CcdDistances, PointTriangleEveryRegion) {
  const Vec3 t0{0, 0, 0}, t1{2, 0, 0}, t2{0, 2, 0};
  EXPECT_DOUBLE_EQ(pt({0.5, 0.5, 3}, t0, t1, t2), 9.0);   // face interior
  EXPECT_DOUBLE_EQ(pt({0.5, 0.5, -3}, t0, t1, t2), 9.0);  // face, other side
  EXPECT_DOUBLE_EQ(pt({-1, -1, 0.5}, t0, t1, t2), 2.25);  // vertex t0
  EXPECT_DOUBLE_EQ(pt({3, -1, 0}, t0, t1, t2), 2.0);      // vertex t1 (coplanar)
  EXPECT_DOUBLE_EQ(pt({-1, 3, 2}, t0, t1, t2), 6.0);      // vertex t2
  EXPECT_DOUBLE_EQ(pt({1, -2, 1}, t0, t1, t2), 5.0);      // edge t0-t1
  EXPECT_NEAR(pt({2, 2, 0}, t0, t1, t2), 2.0, 1e-15);     // edge t1-t2 (coplanar)
  EXPECT_DOUBLE_EQ(pt({-3, 1, 4}, t0, t1, t2), 25.0);     // edge t2-t0
  EXPECT_DOUBLE_EQ(pt({0.5, 0.5, 0}, t0, t1, t2), 0.0);   // on the face
  EXPECT_DOUBLE_EQ(pt({2, 0, 0}, t0, t1, t2), 0.0);       // on a vertex
  // Degenerate triangles: collinear vertices act as the segment, coincident as the point.
  EXPECT_DOUBLE_EQ(pt({1, 1, 1}, {0, 0, 0}, {1, 0, 0}, {2, 0, 0}), 2.0);
  EXPECT_DOUBLE_EQ(pt({3, 1, 0}, {0, 0, 0}, {1, 0, 0}, {2, 0, 0}), 2.0);
  EXPECT_DOUBLE_EQ(pt({1, 1, 1}, {0, 0, 0}, {0, 0, 0}, {0, 0, 0}), 3.0);
}

TEST(CcdDistances, EdgeEdgeEveryCase) {
  EXPECT_DOUBLE_EQ(ee({-1, 0, 1}, {1, 0, 1}, {0, -1, 0}, {0, 1, 0}), 1.0);  // skew, interior
  EXPECT_DOUBLE_EQ(ee({-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0}), 0.0);  // intersecting
  EXPECT_DOUBLE_EQ(ee({0, 0, 0}, {2, 0, 0}, {1, 1, 0}, {3, 1, 0}), 1.0);    // parallel, overlap
  EXPECT_DOUBLE_EQ(ee({0, 0, 0}, {1, 0, 0}, {3, 1, 0}, {4, 1, 0}), 5.0);    // parallel, apart
  EXPECT_DOUBLE_EQ(ee({0, 0, 0}, {1, 0, 0}, {3, 0, 0}, {5, 0, 0}), 4.0);    // collinear
  EXPECT_DOUBLE_EQ(ee({0, 0, 0}, {1, 0, 0}, {1, 0, 0}, {5, 0, 0}), 0.0);    // touching ends
  EXPECT_DOUBLE_EQ(ee({0, 0, 0}, {2, 0, 0}, {1, 1, 0}, {1, 3, 0}), 1.0);    // end to interior
  EXPECT_DOUBLE_EQ(ee({0, 0, 0}, {1, 0, 0}, {2, -1, 1}, {2, 1, 1}), 2.0);   // one side clamped
  EXPECT_DOUBLE_EQ(ee({0, 0, 0}, {1, 0, 0}, {2, 1, 1}, {3, 2, 1}), 3.0);    // both clamped
  EXPECT_DOUBLE_EQ(ee({0, 0, 0}, {0, 0, 0}, {1, -1, 1}, {1, 1, 1}), 2.0);   // degenerate edge
  EXPECT_DOUBLE_EQ(ee({0, 0, 0}, {0, 0, 0}, {1, 2, 2}, {1, 2, 2}), 9.0);    // two points
  EXPECT_DOUBLE_EQ(ee({0, 0, 0}, {2, 0, 0}, {2, 0, 0}, {0, 0, 0}), 0.0);    // same edge
}

// Nearly parallel edges crossing over each other at a known gap g (closest points interior):
// the distance must be g to the stated bound (about 5e-11 of the edge length) at every angle,
// including those where the textbook normal equations lose all digits. The frame is rotated
// so that no coordinate is exact.
TEST(CcdDistances, NearlyParallelCrossingIsAccurate) {
  const double c = std::cos(0.7), s = std::sin(0.7), c2 = std::cos(0.3), s2 = std::sin(0.3);
  auto rotate = [&](const Vec3& p) {  // about z by 0.7 rad, then about x by 0.3 rad
    const Vec3 q{c * p[0] - s * p[1], s * p[0] + c * p[1], p[2]};
    return Vec3{q[0], c2 * q[1] - s2 * q[2], s2 * q[1] + c2 * q[2]};
  };
  for (double angle : {1e-2, 1e-4, 1e-6, 1e-8, 1e-10, 1e-12, 0.0})
    for (double gap : {1e-3, 1e-7, 1e-10, 0.0}) {
      // Edge a along x through the origin; edge b at height gap, turned by `angle` in the
      // plane z = gap, crossing over a at x = 0.1.
      const Vec3 a0 = rotate({-0.6, 0, 0}), a1 = rotate({0.5, 0, 0});
      const double ca = std::cos(angle), sa = std::sin(angle);
      const Vec3 b0 = rotate({0.1 - 0.7 * ca, -0.7 * sa, gap}), b1 = rotate({0.1 + 0.4 * ca, 0.4 * sa, gap});
      const double d = std::sqrt(ee(a0, a1, b0, b1));
      EXPECT_NEAR(d, gap, 5e-11) << "angle " << angle << " gap " << gap;
      EXPECT_LE(d, gap + 5e-11) << "an overestimate would let the CCD step over the contact";
    }
}

// Random configurations of unit size in several families that stress the case decisions.
TEST(CcdDistances, RandomAgainstPatternSearchReference) {
  std::mt19937_64 rng(20240611);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  auto rnd = [&] { return Vec3{u(rng), u(rng), u(rng)}; };
  for (int trial = 0; trial < 6000; ++trial) {
    const int family = trial % 6;
    Vec3 p = rnd(), a = rnd(), b = rnd(), c = rnd();
    if (family == 1) p[2] = a[2] = b[2] = c[2] = 0.0;  // coplanar
    if (family == 2)                                   // degenerate triangle
      for (int k = 0; k < 3; ++k) c[k] = a[k] + 0.7 * (b[k] - a[k]);
    if (family == 3) {  // point close to the face
      for (int k = 0; k < 3; ++k) p[k] = (a[k] + b[k] + c[k]) / 3.0;
      p[2] += 1e-7 * u(rng);
    }
    const double mine = pt(p, a, b, c), ref = reference_point_triangle(p, a, b, c);
    EXPECT_NEAR(mine, ref, 1e-11) << "point-triangle trial " << trial;

    Vec3 a0 = rnd(), a1 = rnd(), b0 = rnd(), b1 = rnd();
    const Vec3 dir{a1[0] - a0[0], a1[1] - a0[1], a1[2] - a0[2]};
    if (family == 1)  // exactly parallel
      for (int k = 0; k < 3; ++k) b1[k] = b0[k] + 0.6 * dir[k];
    if (family == 2) {  // nearly parallel, crossing
      const Vec3 off = rnd();
      for (int k = 0; k < 3; ++k) {
        b0[k] = a0[k] + 1e-4 * off[k] - 0.2 * dir[k];
        b1[k] = a1[k] - 1e-4 * off[k] + 0.1 * dir[k];
      }
    }
    if (family == 3) a0[2] = a1[2] = b0[2] = b1[2] = 0.0;  // coplanar
    if (family == 4) b1 = b0;                              // degenerate edge
    const double mine_ee = ee(a0, a1, b0, b1), ref_ee = reference_edge_edge(a0, a1, b0, b1);
    EXPECT_NEAR(mine_ee, ref_ee, 1e-11) << "edge-edge trial " << trial << " family " << family;
  }
}

}  // namespace
