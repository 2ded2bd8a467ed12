// Unsigned squared distances between the primitives the CCD advances: point-segment,
// point-triangle and segment-segment, each the true Euclidean distance between the closest
// points (interior, edge or vertex). The CCD only needs values, not derivatives, so these are
// written for robustness rather than smoothness (src/contact/geometry/ has the
// differentiable versions used by the barrier; the narrow phase deliberately does not depend
// on them; the only shared header is math/vector3.hpp).
//
// Robustness rule used throughout: every candidate is either the squared length of a vector
// between two points that lie on the primitives (an upper bound of the true distance up to
// rounding) or a lower bound of it (distance to the supporting plane). The result is the
// minimum of the candidates, so rounding in a case decision (inside/outside, parallel or
// not) can only lower the value near the decision boundary, where the candidates agree —
// which for CCD means an earlier stop, never a missed contact.
#pragma once
#include "math/host_device.hpp"
#include "math/vector3.hpp"

namespace dipc::contact::ccd {

// Closest point of segment [a, b] to p at a + s (b - a), s = clamp(((p-a).(b-a)) / |b-a|^2);
// a degenerate segment (a == b) is the point a.
DIPC_HD double point_segment_distance_squared(const double p[3], const double a[3], const double b[3]) {
  double e[3], w[3];
  subtract3(b, a, e);
  subtract3(p, a, w);
  const double ee = dot3(e, e);
  const double s = ee > 0.0 ? clamp01(dot3(w, e) / ee) : 0.0;
  const double r[3] = {w[0] - s * e[0], w[1] - s * e[1], w[2] - s * e[2]};
  return dot3(r, r);
}

// Point-triangle distance (Ericson, "Real-Time Collision Detection", 2005, sec. 5.1.5,
// reorganised): if the projection of p onto the triangle's plane falls inside the triangle
// the distance is the plane distance (n.(p - t0))^2 / |n|^2; otherwise the closest point lies
// on the boundary, so it is the smallest of the three point-segment distances. The boundary
// candidates are always evaluated, which also covers degenerate (zero-area) triangles.
DIPC_HD double point_triangle_distance_squared(const double p[3], const double t0[3], const double t1[3],
                                               const double t2[3]) {
  double best = point_segment_distance_squared(p, t0, t1);
  const double d12 = point_segment_distance_squared(p, t1, t2);
  const double d20 = point_segment_distance_squared(p, t2, t0);
  best = d12 < best ? d12 : best;
  best = d20 < best ? d20 : best;

  double e0[3], e1[3], n[3];
  subtract3(t1, t0, e0);
  subtract3(t2, t0, e1);
  cross3(e0, e1, n);
  const double nn = dot3(n, n);
  if (!(nn > 0.0)) return best;

  // p projects inside iff it lies on the inner side of all three edges:
  // ((t_{i+1} - t_i) x (p - t_i)) . n >= 0.
  const double* v[3] = {t0, t1, t2};
  for (int i = 0; i < 3; ++i) {
    double edge[3], w[3], c[3];
    subtract3(v[(i + 1) % 3], v[i], edge);
    subtract3(p, v[i], w);
    cross3(edge, w, c);
    if (dot3(c, n) < 0.0) return best;
  }
  double w[3];
  subtract3(p, t0, w);
  const double h = dot3(n, w);
  const double plane = h * h / nn;
  return plane < best ? plane : best;
}

// Segment-segment distance. The squared distance |w + s u - t v|^2 (u = a1 - a0,
// v = b1 - b0, w = a0 - b0) is a convex quadratic over the square (s, t) in [0, 1]^2: its
// minimum is the stationary point of the infinite lines when that lies in the square, and
// otherwise on the square's boundary, where each side is a point-segment distance from an
// endpoint. Parallel lines have a line of minimisers that reaches the boundary whenever it
// meets the square, so the boundary candidates alone are exact there.
//
// Nearly parallel lines (angle theta small) are where rounding matters. The textbook normal
// equations (Ericson sec. 5.1.9) divide by uu vv - uv^2, which cancels to a relative error of
// eps / theta^2; the stationary point then lands up to (eps / theta^2) |u| away along the
// lines, and |w + s u - t v|^2 there overestimates the distance (a missed contact for the
// CCD). Instead:
//  - det = |u x v|^2 and the numerators are the Lagrange identities
//      uv vw - vv uw = (u x v).(v x w),  uu vw - uv uw = (u x v).(u x w),
//    whose cross products carry a relative error of only eps / theta;
//  - the interior candidate is the line-line distance (r.n)^2 / |n|^2 (n = u x v), measured
//    from the computed near-closest points r = w + s u - t v. It never exceeds the segment
//    distance (a lower bound) and equals it when the minimiser is interior. The stationary
//    point is off by (eps / theta) |u| along the lines, and n's direction by eps / theta, so
//    r.n / |n| is off by about (eps / theta)^2 |u| (plus a few ulps).
// An error in the inside/outside decision moves the stationary point by (eps / theta) |u|
// along the lines, which changes the distance at the boundary by about theta times that,
// eps |u|. Below sin^2 theta = kNearlyParallelSin2 (theta ~ 3e-11) the lines count as
// parallel and only the boundary candidates are used; for lines that do cross inside the
// square they overestimate by at most theta max(|u|, |v|). Both errors stay below about
// 5e-11 of the edge length, the bound the CCD contract (time_of_impact.hpp) states.
constexpr double kNearlyParallelSin2 = 1e-21;

DIPC_HD double edge_edge_distance_squared(const double a0[3], const double a1[3], const double b0[3],
                                          const double b1[3]) {
  double best = point_segment_distance_squared(a0, b0, b1);
  const double c1 = point_segment_distance_squared(a1, b0, b1);
  const double c2 = point_segment_distance_squared(b0, a0, a1);
  const double c3 = point_segment_distance_squared(b1, a0, a1);
  best = c1 < best ? c1 : best;
  best = c2 < best ? c2 : best;
  best = c3 < best ? c3 : best;

  double u[3], v[3], w[3], n[3];
  subtract3(a1, a0, u);
  subtract3(b1, b0, v);
  subtract3(a0, b0, w);
  cross3(u, v, n);
  const double nn = dot3(n, n);
  if (!(nn > kNearlyParallelSin2 * dot3(u, u) * dot3(v, v))) return best;
  double vw[3], uw[3];
  cross3(v, w, vw);
  cross3(u, w, uw);
  // Stationary point of |w + s u - t v|^2 (normal equations, numerators as above).
  const double s = dot3(n, vw) / nn;
  const double t = dot3(n, uw) / nn;
  if (s < 0.0 || s > 1.0 || t < 0.0 || t > 1.0) return best;
  const double r[3] = {w[0] + s * u[0] - t * v[0], w[1] + s * u[1] - t * v[1], w[2] + s * u[2] - t * v[2]};
  const double h = dot3(r, n);
  const double interior = h * h / nn;
  return interior < best ? interior : best;
}

}  // namespace dipc::contact::ccd
