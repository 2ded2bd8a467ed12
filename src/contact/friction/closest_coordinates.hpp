// Closest-point coordinates of the contact pairs, for friction's relative-velocity operator
// (Li et al. 2020, "Incremental Potential Contact", §5: the lagged closest-point coordinates
// that define the relative sliding of the two closest points). Host/device point functions:
//  - point-triangle: barycentric (beta1, beta2) of the closest point of the triangle,
//    c = t0 + beta1 (t1 - t0) + beta2 (t2 - t0), clamped to the triangle, with the feature
//    (face, edge or vertex) it lies on;
//  - edge-edge: parameters (alpha, beta) of the closest points ea0 + alpha (ea1 - ea0) and
//    eb0 + beta (eb1 - eb0), clamped to the segments;
//  - point-plane: the orthogonal projection onto an obstacle half-space's boundary plane.
// Computed here rather than taken from the distance code so friction has no dependency on it.
#pragma once
#include <cmath>

#include "math/host_device.hpp"
#include "math/vector3.hpp"

namespace dipc::contact {

// The feature of a triangle on which the closest point to a query point lies. Edge ij joins
// vertices i and j.
enum class TriangleFeature : int { kFace, kEdge01, kEdge12, kEdge20, kVertex0, kVertex1, kVertex2 };

// Parameter s in [0,1] of the point of segment [a, b] closest to p (0 for a zero-length
// segment): the unconstrained minimiser ((p-a).(b-a))/|b-a|^2 of the convex quadratic,
// clamped.
DIPC_HD double point_segment_closest_parameter(const double p[3], const double a[3], const double b[3]) {
  double ab[3], ap[3];
  subtract3(b, a, ab);
  subtract3(p, a, ap);
  const double len2 = dot3(ab, ab);
  if (!(len2 > 0.0)) return 0.0;
  return clamp01(dot3(ap, ab) / len2);
}

// Barycentric coordinates beta = (beta1, beta2) of the point of triangle (t0, t1, t2) closest
// to p; returns the feature it lies on. Voronoi-region classification of Ericson, "Real-Time
// Collision Detection" (2005), §5.1.5: each region test uses only dot products, and every
// division is by a squared edge length or by |(t1-t0) x (t2-t0)|^2, positive for a
// non-degenerate triangle. A degenerate (zero-area) triangle falls back to its closest edge.
DIPC_HD TriangleFeature point_triangle_closest_coordinates(const double p[3], const double t0[3], const double t1[3],
                                                           const double t2[3], double beta[2]) {
  double ab[3], ac[3], ap[3], bc[3], normal[3];
  subtract3(t1, t0, ab);
  subtract3(t2, t0, ac);
  subtract3(t2, t1, bc);
  subtract3(p, t0, ap);
  cross3(ab, ac, normal);
  const double area2 = dot3(normal, normal);
  const double scale2 = dot3(ab, ab) * dot3(ac, ac);
  // Relative test: |ab x ac|^2 = |ab|^2 |ac|^2 sin^2(angle) below ~ eps^2 means the three
  // vertices are collinear to working precision.
  if (!(area2 > 1e-28 * scale2)) {
    const double s01 = point_segment_closest_parameter(p, t0, t1);
    const double s12 = point_segment_closest_parameter(p, t1, t2);
    const double s20 = point_segment_closest_parameter(p, t2, t0);
    double best = 0.0;
    int edge = -1;
    const double* ends[3][2] = {{t0, t1}, {t1, t2}, {t2, t0}};
    const double s[3] = {s01, s12, s20};
    for (int e = 0; e < 3; ++e) {
      double c[3], d[3];
      for (int i = 0; i < 3; ++i) c[i] = ends[e][0][i] + s[e] * (ends[e][1][i] - ends[e][0][i]);
      subtract3(p, c, d);
      const double dist2 = dot3(d, d);
      if (edge < 0 || dist2 < best) {
        best = dist2;
        edge = e;
      }
    }
    if (edge == 0) {
      beta[0] = s01;
      beta[1] = 0.0;
      return s01 == 0.0 ? TriangleFeature::kVertex0
                        : (s01 == 1.0 ? TriangleFeature::kVertex1 : TriangleFeature::kEdge01);
    }
    if (edge == 1) {
      beta[0] = 1.0 - s12;
      beta[1] = s12;
      return s12 == 0.0 ? TriangleFeature::kVertex1
                        : (s12 == 1.0 ? TriangleFeature::kVertex2 : TriangleFeature::kEdge12);
    }
    beta[0] = 0.0;
    beta[1] = 1.0 - s20;
    return s20 == 0.0 ? TriangleFeature::kVertex2 : (s20 == 1.0 ? TriangleFeature::kVertex0 : TriangleFeature::kEdge20);
  }

  const double d1 = dot3(ab, ap), d2 = dot3(ac, ap);
  if (d1 <= 0.0 && d2 <= 0.0) {
    beta[0] = beta[1] = 0.0;
    return TriangleFeature::kVertex0;
  }
  double bp[3];
  subtract3(p, t1, bp);
  const double d3 = dot3(ab, bp), d4 = dot3(ac, bp);
  if (d3 >= 0.0 && d4 <= d3) {
    beta[0] = 1.0;
    beta[1] = 0.0;
    return TriangleFeature::kVertex1;
  }
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
    beta[0] = d1 / (d1 - d3);  // d1 - d3 = |ab|^2
    beta[1] = 0.0;
    return TriangleFeature::kEdge01;
  }
  double cp[3];
  subtract3(p, t2, cp);
  const double d5 = dot3(ab, cp), d6 = dot3(ac, cp);
  if (d6 >= 0.0 && d5 <= d6) {
    beta[0] = 0.0;
    beta[1] = 1.0;
    return TriangleFeature::kVertex2;
  }
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
    beta[0] = 0.0;
    beta[1] = d2 / (d2 - d6);  // d2 - d6 = |ac|^2
    return TriangleFeature::kEdge20;
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));  // denominator = |t2 - t1|^2
    beta[0] = 1.0 - w;
    beta[1] = w;
    return TriangleFeature::kEdge12;
  }
  // Inside the face: va, vb, vc are the (scaled) barycentric areas, va + vb + vc = area2.
  const double inv = 1.0 / (va + vb + vc);
  beta[0] = vb * inv;
  beta[1] = vc * inv;
  return TriangleFeature::kFace;
}

// Parameters (alpha, beta) in [0,1]^2 minimising |ea0 + alpha ea - (eb0 + beta eb)|^2 with
// ea = ea1 - ea0, eb = eb1 - eb0. Ericson, "Real-Time Collision Detection", §5.1.9: solve
// the 2x2 normal equations, clamp alpha, take the optimal beta for it, and when beta has to
// be clamped re-optimise alpha for the clamped beta; this yields the constrained minimiser
// of the convex problem. Parallel edges (sin^2 of their angle below ~1e-14) have a whole
// segment of minimisers; alpha = 0 (then the optimal beta) is taken. Zero-length edges
// reduce to point-segment.
DIPC_HD void edge_edge_closest_coordinates(const double ea0[3], const double ea1[3], const double eb0[3],
                                           const double eb1[3], double* alpha, double* beta) {
  double ea[3], eb[3], r[3];
  subtract3(ea1, ea0, ea);
  subtract3(eb1, eb0, eb);
  subtract3(ea0, eb0, r);
  const double a = dot3(ea, ea), e = dot3(eb, eb), f = dot3(eb, r);
  if (!(a > 0.0) && !(e > 0.0)) {
    *alpha = *beta = 0.0;
    return;
  }
  if (!(a > 0.0)) {
    *alpha = 0.0;
    *beta = clamp01(f / e);
    return;
  }
  const double c = dot3(ea, r);
  if (!(e > 0.0)) {
    *beta = 0.0;
    *alpha = clamp01(-c / a);
    return;
  }
  const double b = dot3(ea, eb);
  const double denom = a * e - b * b;  // = |ea x eb|^2 >= 0
  double s = denom > 1e-14 * a * e ? clamp01((b * f - c * e) / denom) : 0.0;
  double t = (b * s + f) / e;
  if (t < 0.0) {
    t = 0.0;
    s = clamp01(-c / a);
  } else if (t > 1.0) {
    t = 1.0;
    s = clamp01((b - c) / a);
  }
  *alpha = s;
  *beta = t;
}

// Closest point c of the plane through `origin` with normal n (any non-zero length) to p,
// c = p - ((p - origin).n / |n|^2) n. Returns the signed distance (p - origin).n / |n|,
// positive on the side n points to (the free side of an obstacle half-space).
DIPC_HD double point_plane_closest_point(const double p[3], const double origin[3], const double n[3], double c[3]) {
  double op[3];
  subtract3(p, origin, op);
  const double n2 = dot3(n, n);
  const double s = dot3(op, n) / n2;
  for (int i = 0; i < 3; ++i) c[i] = p[i] - s * n[i];
  return s * sqrt(n2);
}

}  // namespace dipc::contact
