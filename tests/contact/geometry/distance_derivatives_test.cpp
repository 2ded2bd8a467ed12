// Central finite-difference checks (value -> gradient -> Hessian) of the point-triangle and
// edge-edge distances for every type, on random configurations built inside each type's
// region (the classifier must agree), over length scales 1e-4..1e4 and including
// zero-distance (coplanar / intersecting) configurations. Also checks that the Hessian is
// symmetric and that the derivatives of the vertices the type does not use are zero.
#include <gtest/gtest.h>

#include <random>
#include <string>

#include "contact/geometry/edge_edge_distance.hpp"
#include "contact/geometry/point_triangle_distance.hpp"
#include "geometry_test_support.hpp"

namespace dipc::contact {
namespace {

using test::Stencil;
using test::Vec3;

test::Derivatives point_triangle_derivatives(PointTriangleType type) {
  auto at = [](const double* x, int i) { return x + 3 * i; };
  return {[=](const double* x) { return point_triangle_distance(at(x, 0), at(x, 1), at(x, 2), at(x, 3), type); },
          [=](const double* x, double* g) {
            point_triangle_distance_gradient(at(x, 0), at(x, 1), at(x, 2), at(x, 3), type, g);
          },
          [=](const double* x, double* H) {
            point_triangle_distance_hessian(at(x, 0), at(x, 1), at(x, 2), at(x, 3), type, H);
          }};
}

test::Derivatives edge_edge_derivatives(EdgeEdgeType type) {
  auto at = [](const double* x, int i) { return x + 3 * i; };
  return {[=](const double* x) { return edge_edge_distance(at(x, 0), at(x, 1), at(x, 2), at(x, 3), type); },
          [=](const double* x, double* g) {
            edge_edge_distance_gradient(at(x, 0), at(x, 1), at(x, 2), at(x, 3), type, g);
          },
          [=](const double* x, double* H) {
            edge_edge_distance_hessian(at(x, 0), at(x, 1), at(x, 2), at(x, 3), type, H);
          }};
}

// FD step and tolerances relative to the length scale L: gradients scale like L and
// Hessians like 1, so floors of 1e-3 L and 1e-3 judge vanishing derivatives absolutely.
void expect_derivatives_match(const test::Derivatives& f, const Stencil& s, double L, const std::string& what) {
  const auto x = s.flat();
  const auto e = test::finite_difference_errors(f, x.data(), 1e-5 * L, 1e-3 * L, 1e-3);
  EXPECT_LT(e.gradient, 1e-6) << what;
  EXPECT_LT(e.hessian, 1e-6) << what;
  EXPECT_LT(e.asymmetry, 1e-14) << what;
}

// Vertices (stacked indices) whose rows and columns must be zero for a type.
void expect_unused_vertices_zero(const test::Derivatives& f, const Stencil& s, const int* ids, int n,
                                 const std::string& what) {
  const auto x = s.flat();
  double g[12], H[144];
  f.gradient(x.data(), g);
  f.hessian(x.data(), H);
  for (int v = 0; v < 4; ++v) {
    bool used = false;
    for (int a = 0; a < n; ++a) used = used || ids[a] == v;
    if (used) continue;
    for (int i = 0; i < 3; ++i) {
      EXPECT_EQ(g[3 * v + i], 0.0) << what;
      for (int j = 0; j < 12; ++j) EXPECT_EQ(H[12 * (3 * v + i) + j], 0.0) << what;
    }
  }
}

const double kScales[] = {1e-4, 1e-2, 1.0, 1e2, 1e4};

TEST(DistanceDerivatives, PointTriangleEveryTypeEveryScale) {
  std::mt19937_64 rng(31);
  for (double L : kScales)
    for (int type = 0; type < 7; ++type)
      for (int k = 0; k < 12; ++k) {
        const double height = (k % 4 == 0) ? 0.0 : test::uniform(rng, -1.0, 1.0);
        const Vec3 offset = {test::uniform(rng, -3, 3) * L, test::uniform(rng, -3, 3) * L,
                             test::uniform(rng, -3, 3) * L};
        const Stencil s = test::point_triangle_of_type(rng, type, height).scaled(L, offset);
        const PointTriangleType t = point_triangle_distance_type(s[0], s[1], s[2], s[3]);
        ASSERT_EQ(static_cast<int>(t), type);
        const std::string what = "type " + std::to_string(type) + " L " + std::to_string(L) + " sample " +
                                 std::to_string(k);
        expect_derivatives_match(point_triangle_derivatives(t), s, L, what);
        int ids[4];
        expect_unused_vertices_zero(point_triangle_derivatives(t), s, ids, point_triangle_type_vertices(t, ids), what);
      }
}

TEST(DistanceDerivatives, EdgeEdgeEveryTypeEveryScale) {
  std::mt19937_64 rng(32);
  for (double L : kScales)
    for (int type = 0; type < 9; ++type)
      for (int k = 0; k < 12; ++k) {
        // Separation 0 (intersecting edges) only where the type is then unique: crossing.
        const bool touching = type == static_cast<int>(EdgeEdgeType::EA_EB) && k % 4 == 0;
        const double separation = touching ? 0.0 : test::uniform(rng, 0.01, 1.0);
        const int* f = test::kEdgeEdgeFeatures[type];
        const Vec3 offset = {test::uniform(rng, -3, 3) * L, test::uniform(rng, -3, 3) * L,
                             test::uniform(rng, -3, 3) * L};
        const Stencil s = test::edge_edge_of_features(rng, f[0], f[1], separation).scaled(L, offset);
        const EdgeEdgeType t = edge_edge_distance_type(s[0], s[1], s[2], s[3]);
        ASSERT_EQ(static_cast<int>(t), type);
        const std::string what = "type " + std::to_string(type) + " L " + std::to_string(L) + " sample " +
                                 std::to_string(k);
        expect_derivatives_match(edge_edge_derivatives(t), s, L, what);
        int ids[4];
        expect_unused_vertices_zero(edge_edge_derivatives(t), s, ids, edge_edge_type_vertices(t, ids), what);
      }
}

// Each distance is invariant under translating all four vertices, so the four 3-blocks of
// its gradient sum to zero: a check of the scatter independent of finite differences.
TEST(DistanceDerivatives, GradientsAreTranslationInvariant) {
  std::mt19937_64 rng(33);
  for (int type = 0; type < 7; ++type) {
    const Stencil s = test::point_triangle_of_type(rng, type, 0.3);
    double g[12];
    point_triangle_distance_gradient(s[0], s[1], s[2], s[3], static_cast<PointTriangleType>(type), g);
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(g[i] + g[3 + i] + g[6 + i] + g[9 + i], 0.0, 1e-13) << type;
  }
  for (int type = 0; type < 9; ++type) {
    const int* f = test::kEdgeEdgeFeatures[type];
    const Stencil s = test::edge_edge_of_features(rng, f[0], f[1], 0.3);
    double g[12];
    edge_edge_distance_gradient(s[0], s[1], s[2], s[3], static_cast<EdgeEdgeType>(type), g);
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(g[i] + g[3 + i] + g[6 + i] + g[9 + i], 0.0, 1e-13) << type;
  }
}

}  // namespace
}  // namespace dipc::contact
