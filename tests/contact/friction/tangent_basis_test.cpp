// Tests of the tangent bases (orthonormal, orthogonal to the contact normal in every
// closest-feature region and in degenerate configurations) and of the relative-velocity
// operator Gamma against a direct computation from independently found closest points.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "contact/friction/lagged_friction.hpp"
#include "contact/friction/relative_velocity.hpp"
#include "contact/friction/tangent_basis.hpp"
#include "friction_test_support.hpp"

namespace dipc::contact {
namespace {

using test::Vec3;

Vec3 column(const double P[6], int j) { return {P[j], P[2 + j], P[4 + j]}; }

void expect_orthonormal(const double P[6]) {
  const Vec3 c0 = column(P, 0), c1 = column(P, 1);
  EXPECT_NEAR(dot(c0, c0), 1.0, 1e-14);
  EXPECT_NEAR(dot(c1, c1), 1.0, 1e-14);
  EXPECT_NEAR(dot(c0, c1), 0.0, 1e-14);
  for (int i = 0; i < 6; ++i) EXPECT_TRUE(std::isfinite(P[i]));
}

void expect_orthogonal_to(const double P[6], const Vec3& normal, double tolerance) {
  const Vec3 n = test::normalized(normal);
  EXPECT_NEAR(dot(column(P, 0), n), 0.0, tolerance);
  EXPECT_NEAR(dot(column(P, 1), n), 0.0, tolerance);
}

TEST(TangentBasis, FromNormalAndReference) {
  std::mt19937_64 rng(21);
  for (int k = 0; k < 1000; ++k) {
    const Vec3 n = test::random_vec3(rng), r = test::random_vec3(rng);
    double P[6];
    tangent_basis_with_reference(n.data(), r.data(), P);
    expect_orthonormal(P);
    expect_orthogonal_to(P, n, 1e-14);
    // The first column lies in span(n, r); (c0, c1, n) is right-handed.
    EXPECT_NEAR(dot(column(P, 0), test::cross(n, r)), 0.0, 1e-13);
    EXPECT_GT(dot(test::cross(column(P, 0), column(P, 1)), n), 0.0);
    tangent_basis_from_normal(n.data(), P);
    expect_orthonormal(P);
    expect_orthogonal_to(P, n, 1e-14);
  }
  // A reference parallel to n, or zero, falls back to a coordinate axis.
  const double n[3] = {0, 0, 3}, r[3] = {0, 0, -1};
  double P[6];
  tangent_basis_with_reference(n, r, P);
  expect_orthonormal(P);
  expect_orthogonal_to(P, {0, 0, 1}, 1e-15);
}

TEST(TangentBasis, PointTriangleAllRegionsOrthogonalToClosestPointDirection) {
  std::mt19937_64 rng(23);
  int counts[7] = {};
  for (int k = 0; k < 3000; ++k) {
    const Vec3 t0 = test::random_vec3(rng), t1 = test::random_vec3(rng), t2 = test::random_vec3(rng);
    const Vec3 p = test::random_vec3(rng, -1.5, 1.5);
    double beta[2], P[6];
    const TriangleFeature f = point_triangle_closest_coordinates(p.data(), t0.data(), t1.data(), t2.data(), beta);
    ++counts[static_cast<int>(f)];
    point_triangle_tangent_basis(p.data(), t0.data(), t1.data(), t2.data(), f, beta, P);
    expect_orthonormal(P);
    const Vec3 c = t0 + beta[0] * (t1 - t0) + beta[1] * (t2 - t0);
    const double dist = test::norm(p - c);
    if (dist < 1e-6) continue;  // the direction of p - c is too inaccurate to test against
    expect_orthogonal_to(P, p - c, 1e-14 / dist);
    if (f == TriangleFeature::kFace) expect_orthogonal_to(P, test::cross(t1 - t0, t2 - t0), 1e-13);
  }
  for (int r = 0; r < 7; ++r) EXPECT_GT(counts[r], 20) << "region " << r;
}

TEST(TangentBasis, PointTriangleNearAndAtContact) {
  const Vec3 t0{0, 0, 0}, t1{1, 0, 0}, t2{0, 1, 0};
  double beta[2], P[6];
  // Point over an edge, in the triangle's plane: the normal lies in the plane (-y), so the
  // basis must contain the z axis, not the triangle plane.
  const Vec3 side{0.5, -1e-6, 0.0};
  TriangleFeature f = point_triangle_closest_coordinates(side.data(), t0.data(), t1.data(), t2.data(), beta);
  point_triangle_tangent_basis(side.data(), t0.data(), t1.data(), t2.data(), f, beta, P);
  expect_orthonormal(P);
  expect_orthogonal_to(P, {0, 1, 0}, 1e-12);
  // Point exactly on the triangle (zero distance): the triangle plane.
  const Vec3 on{0.2, 0.3, 0.0};
  f = point_triangle_closest_coordinates(on.data(), t0.data(), t1.data(), t2.data(), beta);
  point_triangle_tangent_basis(on.data(), t0.data(), t1.data(), t2.data(), f, beta, P);
  expect_orthonormal(P);
  expect_orthogonal_to(P, {0, 0, 1}, 1e-15);
  // Point exactly on an edge: also the triangle plane.
  const Vec3 on_edge{0.4, 0.0, 0.0};
  f = point_triangle_closest_coordinates(on_edge.data(), t0.data(), t1.data(), t2.data(), beta);
  point_triangle_tangent_basis(on_edge.data(), t0.data(), t1.data(), t2.data(), f, beta, P);
  expect_orthonormal(P);
  expect_orthogonal_to(P, {0, 0, 1}, 1e-15);
  // Point 1e-9 above a vertex.
  const Vec3 above{0, 0, 1e-9};
  f = point_triangle_closest_coordinates(above.data(), t0.data(), t1.data(), t2.data(), beta);
  point_triangle_tangent_basis(above.data(), t0.data(), t1.data(), t2.data(), f, beta, P);
  expect_orthonormal(P);
  expect_orthogonal_to(P, {0, 0, 1}, 1e-15);
  // Zero-area triangle touching the point: a plane containing the segment.
  const Vec3 d0{0, 0, 0}, d1{1, 0, 0}, d2{2, 0, 0}, q{0.5, 0, 0};
  f = point_triangle_closest_coordinates(q.data(), d0.data(), d1.data(), d2.data(), beta);
  point_triangle_tangent_basis(q.data(), d0.data(), d1.data(), d2.data(), f, beta, P);
  expect_orthonormal(P);
  EXPECT_NEAR(P[0] * P[0] + P[1] * P[1], 1.0, 1e-15);  // x axis in span(P): |P^T x| = 1
}

TEST(TangentBasis, EdgeEdgeOrthogonalToClosestPointDirection) {
  std::mt19937_64 rng(25);
  for (int k = 0; k < 3000; ++k) {
    const Vec3 a0 = test::random_vec3(rng), a1 = test::random_vec3(rng), b0 = test::random_vec3(rng),
               b1 = test::random_vec3(rng);
    double alpha, beta, P[6];
    edge_edge_closest_coordinates(a0.data(), a1.data(), b0.data(), b1.data(), &alpha, &beta);
    edge_edge_tangent_basis(a0.data(), a1.data(), b0.data(), b1.data(), alpha, beta, P);
    expect_orthonormal(P);
    const Vec3 d = (a0 + alpha * (a1 - a0)) - (b0 + beta * (b1 - b0));
    if (test::norm(d) < 1e-6) continue;
    expect_orthogonal_to(P, d, 1e-14 / test::norm(d));
  }
}

TEST(TangentBasis, EdgeEdgeDegenerate) {
  double P[6], alpha, beta;
  // Crossing edges touching: the plane of both edges.
  const Vec3 a0{-1, 0, 0}, a1{1, 0, 0}, b0{0, -1, 0}, b1{0, 1, 0};
  edge_edge_closest_coordinates(a0.data(), a1.data(), b0.data(), b1.data(), &alpha, &beta);
  edge_edge_tangent_basis(a0.data(), a1.data(), b0.data(), b1.data(), alpha, beta, P);
  expect_orthonormal(P);
  expect_orthogonal_to(P, {0, 0, 1}, 1e-15);
  // Parallel edges 1e-4 apart: orthogonal to the separation.
  const Vec3 c0{0, 1e-4, 0}, c1{2, 1e-4, 0};
  edge_edge_closest_coordinates(a0.data(), a1.data(), c0.data(), c1.data(), &alpha, &beta);
  edge_edge_tangent_basis(a0.data(), a1.data(), c0.data(), c1.data(), alpha, beta, P);
  expect_orthonormal(P);
  expect_orthogonal_to(P, {0, 1, 0}, 1e-12);
  // Collinear overlapping edges (zero distance, parallel): a plane containing the edges.
  const Vec3 e0{0.5, 0, 0}, e1{3, 0, 0};
  edge_edge_closest_coordinates(a0.data(), a1.data(), e0.data(), e1.data(), &alpha, &beta);
  edge_edge_tangent_basis(a0.data(), a1.data(), e0.data(), e1.data(), alpha, beta, P);
  expect_orthonormal(P);
  EXPECT_NEAR(P[0] * P[0] + P[1] * P[1], 1.0, 1e-15);
  // Both edges collapsed to the same point.
  const Vec3 z{1, 2, 3};
  edge_edge_tangent_basis(z.data(), z.data(), z.data(), z.data(), 0.0, 0.0, P);
  expect_orthonormal(P);
}

TEST(TangentBasis, PointPlaneOrthogonalToNormal) {
  std::mt19937_64 rng(27);
  for (int k = 0; k < 500; ++k) {
    const Vec3 n = test::random_vec3(rng);
    const LaggedPointPlaneFriction f = point_plane_lagged_friction(n.data(), 0.5, 2.0, 1e-3);
    expect_orthonormal(f.basis);
    expect_orthogonal_to(f.basis, n, 1e-14);
  }
}

// Gamma v compared with the velocity of p minus the velocity of the material point of the
// triangle at the closest point found by the independent reference algorithm; Gamma x is the
// vector between the closest points.
TEST(RelativeVelocity, PointTriangleMatchesDirectComputation) {
  std::mt19937_64 rng(29);
  for (int k = 0; k < 2000; ++k) {
    const Vec3 t0 = test::random_vec3(rng), t1 = test::random_vec3(rng), t2 = test::random_vec3(rng);
    const Vec3 p = test::random_vec3(rng, -1.5, 1.5);
    const auto x = test::stack(p, t0, t1, t2);
    const LaggedPairFriction f = point_triangle_lagged_friction(x.data(), 0.3, 1.0, 1e-3);
    const auto ref = test::reference_point_triangle(p, t0, t1, t2);
    const Vec3 vp = test::random_vec3(rng), v0 = test::random_vec3(rng), v1 = test::random_vec3(rng),
               v2 = test::random_vec3(rng);
    const auto v = test::stack(vp, v0, v1, v2);
    const Vec3 direct = vp - ((1 - ref[0] - ref[1]) * v0 + ref[0] * v1 + ref[1] * v2);
    double r[3];
    apply_relative_velocity(f.weights, v.data(), r);
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(r[a], direct[a], 1e-10) << "sample " << k;
    const Vec3 c = t0 + ref[0] * (t1 - t0) + ref[1] * (t2 - t0);
    apply_relative_velocity(f.weights, x.data(), r);
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(r[a], (p - c)[a], 1e-10);
  }
}

TEST(RelativeVelocity, EdgeEdgeMatchesDirectComputation) {
  std::mt19937_64 rng(31);
  for (int k = 0; k < 2000; ++k) {
    const Vec3 a0 = test::random_vec3(rng), a1 = test::random_vec3(rng), b0 = test::random_vec3(rng),
               b1 = test::random_vec3(rng);
    const auto x = test::stack(a0, a1, b0, b1);
    const LaggedPairFriction f = edge_edge_lagged_friction(x.data(), 0.3, 1.0, 1e-3);
    const auto ref = test::reference_edge_edge(a0, a1, b0, b1);
    const Vec3 va0 = test::random_vec3(rng), va1 = test::random_vec3(rng), vb0 = test::random_vec3(rng),
               vb1 = test::random_vec3(rng);
    const auto v = test::stack(va0, va1, vb0, vb1);
    const Vec3 direct = ((1 - ref[0]) * va0 + ref[0] * va1) - ((1 - ref[1]) * vb0 + ref[1] * vb1);
    double r[3];
    apply_relative_velocity(f.weights, v.data(), r);
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(r[a], direct[a], 1e-9) << "sample " << k;
    const Vec3 d = (a0 + ref[0] * (a1 - a0)) - (b0 + ref[1] * (b1 - b0));
    apply_relative_velocity(f.weights, x.data(), r);
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(r[a], d[a], 1e-9);
  }
}

TEST(RelativeVelocity, TransposeIsAdjointAndTranslationsCancel) {
  std::mt19937_64 rng(33);
  const Vec3 a0{0, 0, 0}, a1{1, 0, 0}, b0{0.3, -1, 0.2}, b1{0.4, 1, 0.25};
  const auto x = test::stack(a0, a1, b0, b1);
  for (const LaggedPairFriction& f :
       {edge_edge_lagged_friction(x.data(), 0.1, 1, 1e-3), point_triangle_lagged_friction(x.data(), 0.1, 1, 1e-3)}) {
    const Vec3 t = test::random_vec3(rng), force = test::random_vec3(rng);
    const auto translation = test::stack(t, t, t, t);
    double r[3], g[12];
    apply_relative_velocity(f.weights, translation.data(), r);
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(r[a], 0.0, 1e-15);
    // <Gamma v, f> = <v, Gamma^T f>
    const auto v = test::stack(test::random_vec3(rng), test::random_vec3(rng), test::random_vec3(rng),
                               test::random_vec3(rng));
    apply_relative_velocity(f.weights, v.data(), r);
    apply_relative_velocity_transpose(f.weights, force.data(), g);
    double lhs = dot({r[0], r[1], r[2]}, force), rhs = 0;
    for (int i = 0; i < 12; ++i) rhs += v[i] * g[i];
    EXPECT_NEAR(lhs, rhs, 1e-14);
  }
}

}  // namespace
}  // namespace dipc::contact
