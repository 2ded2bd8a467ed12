// Near-degenerate configurations of the distances: a point exactly over a triangle edge or
// vertex (where neighbouring types meet, their values and gradients must agree: the
// distance is C1), coplanar points, degenerate triangles, exactly and nearly parallel
// edges (never a division by ~0; the distance stays exact), and a point close to a long
// edge far from its endpoints (no cancellation in the point-line distance).
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "contact/geometry/edge_edge_distance.hpp"
#include "contact/geometry/point_line.hpp"
#include "contact/geometry/point_triangle_distance.hpp"
#include "geometry_test_support.hpp"

namespace dipc::contact {
namespace {

using test::Stencil;
using test::Vec3;
using test::operator+;
using test::operator-;
using test::operator*;
using PT = PointTriangleType;
using EE = EdgeEdgeType;

const double kScales[] = {1e-4, 1e-2, 1.0, 1e2, 1e4};

test::Derivatives pt_derivatives(PT type) {
  return {[=](const double* x) { return point_triangle_distance(x, x + 3, x + 6, x + 9, type); },
          [=](const double* x, double* g) { point_triangle_distance_gradient(x, x + 3, x + 6, x + 9, type, g); },
          [=](const double* x, double* H) { point_triangle_distance_hessian(x, x + 3, x + 6, x + 9, type, H); }};
}

test::Derivatives ee_derivatives(EE type) {
  return {[=](const double* x) { return edge_edge_distance(x, x + 3, x + 6, x + 9, type); },
          [=](const double* x, double* g) { edge_edge_distance_gradient(x, x + 3, x + 6, x + 9, type, g); },
          [=](const double* x, double* H) { edge_edge_distance_hessian(x, x + 3, x + 6, x + 9, type, H); }};
}

void expect_fd_match(const test::Derivatives& f, const Stencil& s, double h, double L, const std::string& what) {
  const auto x = s.flat();
  const auto e = test::finite_difference_errors(f, x.data(), h, 1e-3 * L, 1e-3);
  EXPECT_LT(e.gradient, 1e-6) << what;
  EXPECT_LT(e.hessian, 1e-6) << what;
}

// Types that meet at a boundary give the same value and gradient there.
void expect_types_agree(const std::vector<PT>& types, const Stencil& s, double L, const std::string& what) {
  double g0[12];
  point_triangle_distance_gradient(s[0], s[1], s[2], s[3], types[0], g0);
  const double d0 = point_triangle_distance(s[0], s[1], s[2], s[3], types[0]);
  for (PT t : types) {
    double g[12];
    point_triangle_distance_gradient(s[0], s[1], s[2], s[3], t, g);
    EXPECT_NEAR(point_triangle_distance(s[0], s[1], s[2], s[3], t), d0, 1e-12 * L * L) << what << int(t);
    for (int i = 0; i < 12; ++i) EXPECT_NEAR(g[i], g0[i], 1e-10 * L) << what << int(t) << " dof " << i;
  }
}

bool contains(const std::vector<PT>& types, PT t) {
  for (PT u : types)
    if (u == t) return true;
  return false;
}

TEST(DegenerateDistances, PointExactlyOverAnEdge) {
  std::mt19937_64 rng(41);
  for (double L : kScales)
    for (int k = 0; k < 10; ++k) {
      const auto t = test::random_triangle(rng);
      const Vec3 n = test::normalized(test::cross(t[1] - t[0], t[2] - t[0]));
      const Vec3 p = t[0] + test::uniform(rng, 0.1, 0.9) * (t[1] - t[0]) + test::uniform(rng, -1, 1) * n;
      const Stencil s = Stencil{{p, t[0], t[1], t[2]}}.scaled(L, {L, -2 * L, 0.5 * L});
      const std::vector<PT> meeting = {PT::P_T, PT::P_E0};
      const PT type = point_triangle_distance_type(s[0], s[1], s[2], s[3]);
      EXPECT_TRUE(contains(meeting, type)) << int(type);
      expect_types_agree(meeting, s, L, "over edge, L " + std::to_string(L));
      for (PT m : meeting)
        expect_fd_match(pt_derivatives(m), s, 1e-5 * L, L, "over edge type " + std::to_string(int(m)));
    }
}

TEST(DegenerateDistances, PointExactlyOverAVertex) {
  std::mt19937_64 rng(42);
  for (double L : kScales)
    for (int k = 0; k < 10; ++k) {
      const auto t = test::random_triangle(rng);
      const Vec3 n = test::normalized(test::cross(t[1] - t[0], t[2] - t[0]));
      const Vec3 p = t[0] + test::uniform(rng, 0.05, 1) * n;
      const Stencil s = Stencil{{p, t[0], t[1], t[2]}}.scaled(L, {-L, 3 * L, L});
      const std::vector<PT> meeting = {PT::P_T, PT::P_E0, PT::P_E2, PT::P_T0};
      const PT type = point_triangle_distance_type(s[0], s[1], s[2], s[3]);
      EXPECT_TRUE(contains(meeting, type)) << int(type);
      expect_types_agree(meeting, s, L, "over vertex, L " + std::to_string(L));
      for (PT m : meeting)
        expect_fd_match(pt_derivatives(m), s, 1e-5 * L, L, "over vertex type " + std::to_string(int(m)));
    }
}

TEST(DegenerateDistances, CoplanarPoints) {
  std::mt19937_64 rng(43);
  for (double L : kScales)
    for (int type = 0; type < 7; ++type) {
      const Stencil s = test::point_triangle_of_type(rng, type, 0.0).scaled(L, {2 * L, 0, -L});
      const PT t = point_triangle_distance_type(s[0], s[1], s[2], s[3]);
      ASSERT_EQ(static_cast<int>(t), type);
      const double d = point_triangle_distance(s[0], s[1], s[2], s[3], t);
      if (t == PT::P_T) {
        EXPECT_LT(d, 1e-24 * L * L);
      } else {
        EXPECT_GT(d, 1e-4 * L * L);
      }
      expect_fd_match(pt_derivatives(t), s, 1e-5 * L, L, "coplanar type " + std::to_string(type));
    }
}

TEST(DegenerateDistances, DegenerateTrianglesUseEdgesAndStayExact) {
  std::mt19937_64 rng(44);
  for (double L : kScales)
    for (int k = 0; k < 20; ++k) {
      // t2 on the line through t0, t1 (inside, outside, or on a vertex), or t1 = t2.
      const Vec3 t0 = {test::uniform(rng, -1, 1), test::uniform(rng, -1, 1), test::uniform(rng, -1, 1)};
      const Vec3 t1 = t0 + test::random_unit(rng);
      const double along = (k % 5 == 0) ? 1.0 : test::uniform(rng, -1, 2);
      const Vec3 t2 = t0 + along * (t1 - t0);
      const Vec3 p = {test::uniform(rng, -2, 2), test::uniform(rng, -2, 2), test::uniform(rng, -2, 2)};
      const Stencil s = Stencil{{p, t0, t1, t2}}.scaled(L, {0, L, 0});
      const PT t = point_triangle_distance_type(s[0], s[1], s[2], s[3]);
      ASSERT_NE(t, PT::P_T);
      const double d = point_triangle_distance(s[0], s[1], s[2], s[3], t);
      EXPECT_NEAR(d, test::reference_point_triangle(s), 1e-12 * L * L);
      expect_fd_match(pt_derivatives(t), s, 1e-5 * L, L, "degenerate triangle " + std::to_string(k));
    }
}

// Edge B is edge A shifted by `separation` along m (orthogonal to A) and by `slide` along A,
// optionally reversed: exactly parallel up to rounding.
Stencil parallel_edges(const Vec3& u, const Vec3& m, double separation, double slide, bool reversed) {
  const Vec3 a0 = {0.3, -0.2, 0.1}, a1 = a0 + u;
  const Vec3 shift = separation * m + slide * u;
  Stencil s{{a0, a1, a0 + shift, a1 + shift}};
  if (reversed) std::swap(s.x[2], s.x[3]);
  return s;
}

TEST(DegenerateDistances, ParallelEdges) {
  std::mt19937_64 rng(45);
  for (double L : kScales)
    for (int k = 0; k < 24; ++k) {
      const Vec3 u = test::uniform(rng, 0.5, 2.0) * test::random_unit(rng);
      const Vec3 m = test::random_orthogonal_unit(rng, test::normalized(u));
      const double separation = (k % 6 == 0) ? 0.0 : test::uniform(rng, 0.01, 1.0);
      // Overlapping (|slide| < 1) and disjoint (|slide| > 1) along the common direction.
      const double slide = test::uniform(rng, -2.0, 2.0);
      const Stencil s = parallel_edges(u, m, separation, slide, k % 2 == 1).scaled(L, {L, L, -L});
      const EE t = edge_edge_distance_type(s[0], s[1], s[2], s[3]);
      ASSERT_NE(t, EE::EA_EB);
      const double d = edge_edge_distance(s[0], s[1], s[2], s[3], t);
      ASSERT_TRUE(std::isfinite(d));
      const double gap = std::max(0.0, std::abs(slide) - 1.0) * test::norm(u);
      EXPECT_NEAR(d, (separation * separation + gap * gap) * L * L, 1e-11 * L * L) << "slide " << slide;
      expect_fd_match(ee_derivatives(t), s, 1e-5 * L, L, "parallel, slide " + std::to_string(slide));
    }
}

// A along x over [-1, 1]; B through (0, 0, delta) in the xy-direction at angle theta, so
// the common normal is z and the distance is exactly delta^2 for every theta > 0.
TEST(DegenerateDistances, NearlyParallelEdges) {
  for (double L : kScales)
    for (double theta : {1e-1, 1e-2, 1e-3, 1e-4, 1e-6, 1e-8, 1e-10, 1e-12}) {
      const double delta = 0.1;
      const Vec3 dir = {std::cos(theta), std::sin(theta), 0.0};
      const Vec3 c = {0.0, 0.0, delta};
      const Stencil s = Stencil{{Vec3{-1, 0, 0}, Vec3{1, 0, 0}, c - 0.8 * dir, c + 0.8 * dir}}.scaled(L, {0, 0, 0});
      const EE t = edge_edge_distance_type(s[0], s[1], s[2], s[3]);
      if (theta >= 1e-8) {
        EXPECT_EQ(t, EE::EA_EB) << theta;
      }
      const double d = edge_edge_distance(s[0], s[1], s[2], s[3], t);
      EXPECT_NEAR(d, delta * delta * L * L, 1e-10 * delta * delta * L * L) << "theta " << theta;
      // The line-line derivatives vary on the scale theta L: step and floors follow it.
      if (theta >= 1e-3) expect_fd_match(ee_derivatives(t), s, 1e-5 * theta * L, L, "theta " + std::to_string(theta));
    }
}

TEST(DegenerateDistances, PointLineKeepsRelativeAccuracyNearALongEdge) {
  for (double L : kScales) {
    const double e0[3] = {3 * L, -2 * L, L}, e1[3] = {5 * L, -2 * L, L};
    for (double delta : {1e-3, 1e-5, 1e-7}) {
      const double p[3] = {4.3 * L, -2 * L + delta * L * 0.6, L + delta * L * 0.8};
      const double d = point_line_distance(p, e0, e1);
      // (0, 0.6, 0.8) delta L is orthogonal to the edge: d = (delta L)^2 up to rounding of p.
      EXPECT_NEAR(d, delta * delta * L * L, 1e-7 * delta * delta * L * L) << "delta " << delta << " L " << L;
    }
  }
}

}  // namespace
}  // namespace dipc::contact
