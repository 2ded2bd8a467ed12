// Tests of the closest-point coordinates: optimality (first-order conditions of the convex
// problems, checked at the extreme points of the feasible set), agreement with an
// independent algorithm, the reported triangle feature, and degenerate configurations.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "contact/friction/closest_coordinates.hpp"
#include "friction_test_support.hpp"

namespace dipc::contact {
namespace {

using test::Vec3;

// c(beta) minimises |p - c|^2 over the triangle iff (c - p).(v - c) >= 0 for every vertex v
// (variational inequality over a convex hull, linear in v). Scaled by the triangle size.
void expect_point_triangle_optimal(const Vec3& p, const Vec3& t0, const Vec3& t1, const Vec3& t2,
                                   const double beta[2]) {
  EXPECT_GE(beta[0], 0.0);
  EXPECT_GE(beta[1], 0.0);
  EXPECT_LE(beta[0] + beta[1], 1.0 + 1e-15);
  const Vec3 c = t0 + beta[0] * (t1 - t0) + beta[1] * (t2 - t0);
  const double L2 = dot(t1 - t0, t1 - t0) + dot(t2 - t0, t2 - t0) + dot(p - t0, p - t0);
  for (const Vec3& v : {t0, t1, t2}) EXPECT_GE(dot(c - p, v - c), -1e-12 * L2);
}

// (alpha, beta) minimises |ca - cb|^2 over [0,1]^2 iff grad . (z - z*) >= 0 at the 4 corners z.
void expect_edge_edge_optimal(const Vec3& a0, const Vec3& a1, const Vec3& b0, const Vec3& b1, double alpha, double beta,
                              double tolerance = 1e-12) {
  EXPECT_GE(alpha, 0.0);
  EXPECT_LE(alpha, 1.0);
  EXPECT_GE(beta, 0.0);
  EXPECT_LE(beta, 1.0);
  const Vec3 ea = a1 - a0, eb = b1 - b0;
  const Vec3 d = (a0 + alpha * ea) - (b0 + beta * eb);
  const double ga = 2 * dot(d, ea), gb = -2 * dot(d, eb);
  const double L2 = dot(ea, ea) + dot(eb, eb) + dot(a0 - b0, a0 - b0);
  for (double s : {0.0, 1.0})
    for (double t : {0.0, 1.0}) EXPECT_GE(ga * (s - alpha) + gb * (t - beta), -tolerance * L2);
}

double point_triangle_distance2(const Vec3& p, const Vec3& t0, const Vec3& t1, const Vec3& t2, const double b[2]) {
  const Vec3 c = t0 + b[0] * (t1 - t0) + b[1] * (t2 - t0);
  return dot(p - c, p - c);
}

TEST(PointTriangleClosestCoordinates, RandomConfigurationsAreOptimalAndMatchReference) {
  std::mt19937_64 rng(3);
  int counts[7] = {};
  for (int k = 0; k < 5000; ++k) {
    const Vec3 t0 = test::random_vec3(rng), t1 = test::random_vec3(rng), t2 = test::random_vec3(rng);
    const Vec3 p = test::random_vec3(rng, -1.5, 1.5);
    double beta[2];
    const TriangleFeature f = point_triangle_closest_coordinates(p.data(), t0.data(), t1.data(), t2.data(), beta);
    ++counts[static_cast<int>(f)];
    expect_point_triangle_optimal(p, t0, t1, t2, beta);
    const auto ref = test::reference_point_triangle(p, t0, t1, t2);
    const double d = point_triangle_distance2(p, t0, t1, t2, beta);
    const double d_ref = point_triangle_distance2(p, t0, t1, t2, ref.data());
    EXPECT_NEAR(d, d_ref, 1e-12 * (1 + d_ref)) << "sample " << k;
    // The feature agrees with the coordinates.
    const double b0 = 1 - beta[0] - beta[1];
    switch (f) {
      case TriangleFeature::kFace: EXPECT_TRUE(beta[0] > 0 && beta[1] > 0 && b0 > 0); break;
      case TriangleFeature::kEdge01: EXPECT_EQ(beta[1], 0.0); break;
      case TriangleFeature::kEdge12: EXPECT_NEAR(b0, 0.0, 1e-15); break;
      case TriangleFeature::kEdge20: EXPECT_EQ(beta[0], 0.0); break;
      case TriangleFeature::kVertex0: EXPECT_TRUE(beta[0] == 0 && beta[1] == 0); break;
      case TriangleFeature::kVertex1: EXPECT_TRUE(beta[0] == 1 && beta[1] == 0); break;
      case TriangleFeature::kVertex2: EXPECT_TRUE(beta[0] == 0 && beta[1] == 1); break;
    }
  }
  for (int r = 0; r < 7; ++r) EXPECT_GT(counts[r], 50) << "region " << r << " not exercised";
}

TEST(PointTriangleClosestCoordinates, HandMadeRegions) {
  const Vec3 t0{0, 0, 0}, t1{1, 0, 0}, t2{0, 1, 0};
  struct Case {
    Vec3 p;
    TriangleFeature feature;
    double b1, b2;
  };
  const Case cases[] = {
      {{0.25, 0.25, 0.1}, TriangleFeature::kFace, 0.25, 0.25},
      {{0.25, 0.25, -1e-9}, TriangleFeature::kFace, 0.25, 0.25},
      {{0.5, -0.3, 0.2}, TriangleFeature::kEdge01, 0.5, 0.0},
      {{-0.3, 0.4, 0.0}, TriangleFeature::kEdge20, 0.0, 0.4},  // in the plane, outside
      {{1.0, 1.0, 0.5}, TriangleFeature::kEdge12, 0.5, 0.5},
      {{-0.2, -0.1, 0.3}, TriangleFeature::kVertex0, 0.0, 0.0},
      {{1.5, -0.1, 0.3}, TriangleFeature::kVertex1, 1.0, 0.0},
      {{-0.1, 1.5, -0.3}, TriangleFeature::kVertex2, 0.0, 1.0},
      {{0.5, 0.0, 1e-7}, TriangleFeature::kEdge01, 0.5, 0.0},   // point over an edge
      {{0.0, 0.0, 1e-7}, TriangleFeature::kVertex0, 0.0, 0.0},  // point over a vertex
  };
  for (const Case& c : cases) {
    double beta[2];
    const TriangleFeature f = point_triangle_closest_coordinates(c.p.data(), t0.data(), t1.data(), t2.data(), beta);
    EXPECT_EQ(static_cast<int>(f), static_cast<int>(c.feature)) << c.p[0] << " " << c.p[1] << " " << c.p[2];
    EXPECT_NEAR(beta[0], c.b1, 1e-15);
    EXPECT_NEAR(beta[1], c.b2, 1e-15);
  }
}

TEST(PointTriangleClosestCoordinates, ScaleInvariantFrom1e4To1e4) {
  std::mt19937_64 rng(5);
  for (double scale : {1e-4, 1e-2, 1.0, 1e2, 1e4})
    for (int k = 0; k < 500; ++k) {
      const Vec3 t0 = scale * test::random_vec3(rng), t1 = scale * test::random_vec3(rng),
                 t2 = scale * test::random_vec3(rng), p = scale * test::random_vec3(rng);
      double beta[2];
      point_triangle_closest_coordinates(p.data(), t0.data(), t1.data(), t2.data(), beta);
      expect_point_triangle_optimal(p, t0, t1, t2, beta);
    }
}

TEST(PointTriangleClosestCoordinates, DegenerateTriangleFallsBackToEdges) {
  const Vec3 t0{0, 0, 0}, t1{1, 0, 0}, t2{2, 0, 0};  // collinear
  const Vec3 p{1.5, 0.3, 0.0};
  double beta[2];
  const TriangleFeature f = point_triangle_closest_coordinates(p.data(), t0.data(), t1.data(), t2.data(), beta);
  EXPECT_TRUE(std::isfinite(beta[0]) && std::isfinite(beta[1]));
  const Vec3 c = t0 + beta[0] * (t1 - t0) + beta[1] * (t2 - t0);
  EXPECT_NEAR(test::norm(p - c), 0.3, 1e-15);
  EXPECT_NE(static_cast<int>(f), static_cast<int>(TriangleFeature::kFace));
  const Vec3 q{0, 0, 0};  // all three vertices equal
  double beta_point[2];
  point_triangle_closest_coordinates(p.data(), q.data(), q.data(), q.data(), beta_point);
  EXPECT_TRUE(std::isfinite(beta_point[0]) && std::isfinite(beta_point[1]));
}

TEST(EdgeEdgeClosestCoordinates, RandomConfigurationsAreOptimalAndMatchReference) {
  std::mt19937_64 rng(7);
  int interior = 0, clamped = 0;
  for (int k = 0; k < 5000; ++k) {
    const Vec3 a0 = test::random_vec3(rng), a1 = test::random_vec3(rng), b0 = test::random_vec3(rng),
               b1 = test::random_vec3(rng);
    double alpha, beta;
    edge_edge_closest_coordinates(a0.data(), a1.data(), b0.data(), b1.data(), &alpha, &beta);
    expect_edge_edge_optimal(a0, a1, b0, b1, alpha, beta);
    const auto ref = test::reference_edge_edge(a0, a1, b0, b1);
    const Vec3 d = (a0 + alpha * (a1 - a0)) - (b0 + beta * (b1 - b0));
    const Vec3 dr = (a0 + ref[0] * (a1 - a0)) - (b0 + ref[1] * (b1 - b0));
    EXPECT_NEAR(dot(d, d), dot(dr, dr), 1e-12 * (1 + dot(dr, dr))) << "sample " << k;
    if (alpha > 0 && alpha < 1 && beta > 0 && beta < 1)
      ++interior;
    else
      ++clamped;
  }
  EXPECT_GT(interior, 200);
  EXPECT_GT(clamped, 200);
}

TEST(EdgeEdgeClosestCoordinates, HandMadeCases) {
  double alpha, beta;
  // Crossing edges, 0.1 apart.
  const Vec3 a0{-1, 0, 0}, a1{1, 0, 0}, b0{0.2, -1, 0.1}, b1{0.2, 1, 0.1};
  edge_edge_closest_coordinates(a0.data(), a1.data(), b0.data(), b1.data(), &alpha, &beta);
  EXPECT_NEAR(alpha, 0.6, 1e-15);
  EXPECT_NEAR(beta, 0.5, 1e-15);
  // Endpoint of b over the interior of a.
  const Vec3 c0{0.5, 0, 0.2}, c1{0.5, 0, 1.0};
  edge_edge_closest_coordinates(a0.data(), a1.data(), c0.data(), c1.data(), &alpha, &beta);
  EXPECT_NEAR(alpha, 0.75, 1e-15);
  EXPECT_EQ(beta, 0.0);
  // Endpoint to endpoint.
  const Vec3 e0{2, 1, 0}, e1{3, 2, 0};
  edge_edge_closest_coordinates(a0.data(), a1.data(), e0.data(), e1.data(), &alpha, &beta);
  EXPECT_EQ(alpha, 1.0);
  EXPECT_EQ(beta, 0.0);
  // Zero-length edges.
  const Vec3 z{0.3, 0.4, 0.5};
  edge_edge_closest_coordinates(z.data(), z.data(), b0.data(), b1.data(), &alpha, &beta);
  EXPECT_EQ(alpha, 0.0);
  EXPECT_NEAR(beta, 0.7, 1e-15);
  edge_edge_closest_coordinates(z.data(), z.data(), z.data(), z.data(), &alpha, &beta);
  EXPECT_EQ(alpha, 0.0);
  EXPECT_EQ(beta, 0.0);
}

TEST(EdgeEdgeClosestCoordinates, ParallelAndNearlyParallelEdges) {
  std::mt19937_64 rng(9);
  for (double angle : {0.0, 1e-12, 1e-9, 1e-6, 1e-3}) {
    for (int k = 0; k < 200; ++k) {
      const Vec3 a0 = test::random_vec3(rng), dir = test::normalized(test::random_vec3(rng));
      Vec3 perp = test::normalized(test::cross(dir, test::random_vec3(rng)));
      const Vec3 a1 = a0 + 1.0 * dir;
      const Vec3 tilted = std::cos(angle) * dir + std::sin(angle) * test::normalized(test::cross(dir, perp));
      std::uniform_real_distribution<double> u(-1.5, 1.5);
      const Vec3 b0 = a0 + 1e-3 * perp + u(rng) * dir;
      const Vec3 b1 = b0 + 0.8 * tilted;
      double alpha, beta;
      edge_edge_closest_coordinates(a0.data(), a1.data(), b0.data(), b1.data(), &alpha, &beta);
      // Parallel edges have a segment of minimisers: optimality up to the variation of the
      // distance along the overlap, |sin(angle)| * length per unit parameter.
      expect_edge_edge_optimal(a0, a1, b0, b1, alpha, beta, 1e-12 + 4 * angle);
      const auto ref = test::reference_edge_edge(a0, a1, b0, b1);
      const Vec3 d = (a0 + alpha * (a1 - a0)) - (b0 + beta * (b1 - b0));
      const Vec3 dr = (a0 + ref[0] * (a1 - a0)) - (b0 + ref[1] * (b1 - b0));
      EXPECT_LE(dot(d, d), dot(dr, dr) + 1e-12 + 4e-3 * angle) << "angle " << angle;
    }
  }
}

TEST(PointPlaneClosestPoint, ProjectsOntoThePlane) {
  const double origin[3] = {1, 2, 3}, n[3] = {0, 0, 2};
  const double p[3] = {4, 5, 3.5};
  double c[3];
  const double s = point_plane_closest_point(p, origin, n, c);
  EXPECT_DOUBLE_EQ(s, 0.5);
  EXPECT_DOUBLE_EQ(c[0], 4);
  EXPECT_DOUBLE_EQ(c[1], 5);
  EXPECT_DOUBLE_EQ(c[2], 3);
  const double q[3] = {0, 0, 1};
  EXPECT_DOUBLE_EQ(point_plane_closest_point(q, origin, n, c), -2.0);  // below: negative
  const double m[3] = {1, 1, 1}, r[3] = {2, 2, 2}, o[3] = {0, 0, 0};
  EXPECT_NEAR(point_plane_closest_point(r, o, m, c), 6 / std::sqrt(3.0), 1e-15);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(c[i], 0.0, 1e-15);
}

}  // namespace
}  // namespace dipc::contact
