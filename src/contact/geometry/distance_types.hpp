// Which feature pair realises the distance between a point and a triangle, or between two
// edges (segments). The distance functions then evaluate only that elementary case
// (point-point, point-line, point-plane, line-line), which is smooth, so its gradient and
// Hessian are exact within the region, and the pieces meet with matching value and
// gradient on the region boundaries (the squared distance to a convex set is C1).
//
// Triangle edges: E0 = t0t1, E1 = t1t2, E2 = t2t0. Edge pair: A = ea0ea1, B = eb0eb1;
// EA0_EB = ea0 closest to the interior of B, EA_EB0 = eb0 closest to the interior of A,
// EA_EB = both closest points interior (line-line), EAi_EBj = two endpoints.
#pragma once
#include "math/host_device.hpp"
#include "math/vector3.hpp"

namespace dipc::contact {

enum class PointTriangleType : int { P_T0, P_T1, P_T2, P_E0, P_E1, P_E2, P_T };

enum class EdgeEdgeType : int { EA0_EB0, EA0_EB1, EA1_EB0, EA1_EB1, EA_EB0, EA_EB1, EA0_EB, EA1_EB, EA_EB };

// A triangle counts as degenerate when |n|^2 <= kDegenerateTriangle * L^4 (n = (t1 - t0) x
// (t2 - t0), L its longest edge), i.e. its height is below 1e-10 L: its plane is then not
// determined in double precision, while its edges still are, and the distance to the
// triangle differs from the distance to its nearest edge by at most that height.
constexpr double kDegenerateTriangle = 1e-20;

// Two edges count as parallel when sin^2 of their angle, |u x v|^2 / (|u|^2 |v|^2), is at
// most kParallelEdges: the line-line distance would divide by ~0 there. The endpoint-to-edge
// distances used instead overestimate the distance by at most ~1e-10 of the edge length.
constexpr double kParallelEdges = 1e-20;

// An edge counts as a point when its squared length is at most kDegenerateEdge times the
// squared distance to the other primitive (or times the other edge's squared length):
// the direction of such an edge is rounding noise, so a point-line or line-line case
// through it would be meaningless, while treating it as its first endpoint moves the
// distance by at most ~1e-10 of that distance scale.
constexpr double kDegenerateEdge = 1e-20;

namespace detail {

// Closest point of segment [e0, e1] to p, classified: returns 0 for e0, 1 for e1, 2 for
// the interior; *distance receives the squared distance. Degenerate segments give e0.
DIPC_HD int point_segment_feature(const double p[3], const double e0[3], const double e1[3], double* distance) {
  double r[3], e[3];
  subtract3(p, e0, r);
  subtract3(e1, e0, e);
  const double re = dot3(r, e);
  const double ee = dot3(e, e);
  int feature = 2;
  double tau = 0.0;
  if (re <= 0.0 || ee <= kDegenerateEdge * dot3(r, r)) {
    feature = 0;
  } else if (re >= ee) {
    feature = 1;
    tau = 1.0;
  } else {
    tau = re / ee;
  }
  for (int i = 0; i < 3; ++i) r[i] -= tau * e[i];
  *distance = squared_norm3(r);
  return feature;
}

// Feature of a segment parameter given as numerator / denominator (denominator > 0),
// without dividing: 0 at or below the start, 1 at or beyond the end, 2 inside.
DIPC_HD int clamped_parameter_feature(double numerator, double denominator) {
  if (numerator <= 0.0) return 0;
  if (numerator >= denominator) return 1;
  return 2;
}

// Edge-edge type from the features (0 start, 1 end, 2 interior) of A and of B.
DIPC_HD EdgeEdgeType edge_edge_type_from_features(int feature_a, int feature_b) {
  if (feature_a == 2 && feature_b == 2) return EdgeEdgeType::EA_EB;
  if (feature_a == 2) return feature_b == 0 ? EdgeEdgeType::EA_EB0 : EdgeEdgeType::EA_EB1;
  if (feature_b == 2) return feature_a == 0 ? EdgeEdgeType::EA0_EB : EdgeEdgeType::EA1_EB;
  if (feature_a == 0) return feature_b == 0 ? EdgeEdgeType::EA0_EB0 : EdgeEdgeType::EA0_EB1;
  return feature_b == 0 ? EdgeEdgeType::EA1_EB0 : EdgeEdgeType::EA1_EB1;
}

}  // namespace detail

// The closest point of the triangle is inside it when p projects inside (the three
// edge-side tests n . ((t_{i+1} - t_i) x (p - t_i)) >= 0); otherwise the squared distance to
// a convex set is minimised on its boundary, so the nearest of the three edges (as
// segments) decides between an edge interior and a vertex. Degenerate triangles skip the
// face test.
DIPC_HD PointTriangleType point_triangle_distance_type(const double p[3], const double t0[3], const double t1[3],
                                                       const double t2[3]) {
  const double* t[3] = {t0, t1, t2};
  double edge[3][3];
  double longest = 0.0;
  for (int i = 0; i < 3; ++i) {
    subtract3(t[(i + 1) % 3], t[i], edge[i]);
    const double l2 = squared_norm3(edge[i]);
    if (l2 > longest) longest = l2;
  }
  double n[3];
  cross3(edge[0], edge[1], n);
  if (squared_norm3(n) > kDegenerateTriangle * longest * longest) {
    bool inside = true;
    for (int i = 0; i < 3 && inside; ++i) {
      double r[3], side[3];
      subtract3(p, t[i], r);
      cross3(edge[i], r, side);
      inside = dot3(n, side) >= 0.0;
    }
    if (inside) return PointTriangleType::P_T;
  }
  int best_edge = 0, best_feature = 0;
  double best_distance = 0.0;
  for (int i = 0; i < 3; ++i) {
    double distance;
    const int feature = detail::point_segment_feature(p, t[i], t[(i + 1) % 3], &distance);
    if (i == 0 || distance < best_distance) {
      best_edge = i;
      best_feature = feature;
      best_distance = distance;
    }
  }
  if (best_feature == 2) return static_cast<PointTriangleType>(static_cast<int>(PointTriangleType::P_E0) + best_edge);
  const int vertex = (best_edge + best_feature) % 3;
  return static_cast<PointTriangleType>(static_cast<int>(PointTriangleType::P_T0) + vertex);
}

// Minimises |ea0 + s u - (eb0 + t v)|^2 over (s, t) in [0, 1]^2 (u = ea1 - ea0,
// v = eb1 - eb0), a convex quadratic, in the order of Ericson, Real-Time Collision
// Detection (2005) §5.1.9: s from the unconstrained minimiser of the lines, clamped; t
// minimising for that s; if t leaves [0, 1] it is clamped and s re-minimised for it. Each
// clamp keeps the KKT conditions, so the result is the constrained minimiser. For parallel
// edges every s minimises the line distance, s = 0 is taken, and the result is an
// endpoint-to-edge or endpoint-endpoint case, never line-line. Degenerate (zero-length)
// edges reduce to point-segment tests. Parameters are compared as numerator /
// denominator, never divided.
DIPC_HD EdgeEdgeType edge_edge_distance_type(const double ea0[3], const double ea1[3], const double eb0[3],
                                             const double eb1[3]) {
  double u[3], v[3], w[3];
  subtract3(ea1, ea0, u);
  subtract3(eb1, eb0, v);
  subtract3(ea0, eb0, w);
  const double a = dot3(u, u), b = dot3(u, v), c = dot3(v, v), d = dot3(u, w), e = dot3(v, w);
  const double ww = dot3(w, w);
  const bool a_is_point = a <= kDegenerateEdge * (c > ww ? c : ww);
  const bool b_is_point = c <= kDegenerateEdge * (a > ww ? a : ww);
  double unused;
  if (a_is_point && b_is_point) return EdgeEdgeType::EA0_EB0;
  if (a_is_point) return detail::edge_edge_type_from_features(0, detail::point_segment_feature(ea0, eb0, eb1, &unused));
  if (b_is_point) return detail::edge_edge_type_from_features(detail::point_segment_feature(eb0, ea0, ea1, &unused), 0);

  // Unconstrained s = ((eb0 - ea0) x v) . n / |n|^2 with n = u x v: triple products instead
  // of (b e - c d) / (a c - b^2), whose differences cancel for nearly parallel edges.
  double n[3], wv[3];
  cross3(u, v, n);
  const double nn = squared_norm3(n);
  int feature_a = 0;
  double s_numerator = 0.0, s_denominator = 1.0;
  if (nn > kParallelEdges * a * c) {
    cross3(w, v, wv);
    s_numerator = -dot3(wv, n);
    s_denominator = nn;
    feature_a = detail::clamped_parameter_feature(s_numerator, s_denominator);
  }
  // t(s) = (b s + e) / c; with s = s_numerator / s_denominator scaled by s_denominator > 0.
  const double s_clamped_numerator = feature_a == 2 ? s_numerator : (feature_a == 1 ? s_denominator : 0.0);
  const double t_numerator = b * s_clamped_numerator + e * s_denominator;
  const double t_denominator = c * s_denominator;
  const int feature_b = detail::clamped_parameter_feature(t_numerator, t_denominator);
  if (feature_b == 0) return detail::edge_edge_type_from_features(detail::clamped_parameter_feature(-d, a), 0);
  if (feature_b == 1) return detail::edge_edge_type_from_features(detail::clamped_parameter_feature(b - d, a), 1);
  return detail::edge_edge_type_from_features(feature_a, 2);
}

}  // namespace dipc::contact
