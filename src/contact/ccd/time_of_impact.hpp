// Conservative continuous collision detection (narrow phase) for linear trajectories:
// point-triangle and edge-edge by additive CCD (additive_ccd.hpp), point-plane in closed
// form. Host/device point functions on plain double arrays; no allocation, no exceptions.
//
// Contract (all three functions). Each vertex moves linearly from its position at t = 0
// (arguments *_t0) to its position at t = 1 (*_t1); t may range up to t_max (normally 1).
// min_separation xi >= 0 is an UNSIGNED distance (not squared; e.g. 0, or a small fraction
// of sqrt(d_hat) to keep a safety margin). The return value t* lies in [0, t_max] and
//   - is conservative: the primitives' unsigned distance stays > xi for all t in [0, t*]
//     (exact-arithmetic guarantee; in floating point the limit is the distance evaluation
//     error: a few ulps of the coordinates, and for nearly parallel edges up to about 5e-11
//     of the edge length, see ccd_distances.hpp).
//     There are no false negatives: if contact (distance <= xi) happens at tau <= t_max,
//     then t* < tau;
//   - is t_max when the distance never gets down to the stopping gap before t_max, in
//     particular exactly t_max for zero relative motion, a rigid common translation, or
//     motion away from each other;
//   - is 0 when the primitives start at distance <= xi, or so close to it that rounding of
//     the coordinates could hide contact (within ccd_defaults::resolution_ulps ulps of the
//     largest coordinate for additive CCD, within the dot-product error for the plane);
//   - may be early (a "false positive"): additive CCD stops as soon as the gap d - xi has
//     shrunk below (1 - s) of its initial value, so a pair that comes close without
//     touching gets t* < t_max, and an oblique approach gets t* below the true impact time.
//     When the gap closes at a constant rate (e.g. a point moving towards the inside of a
//     face, or skew edges closing on interior points), t* >= (1 - sqrt(1 - s)) * tau,
//     about 0.68 tau for s = 0.9. At t* the gap is still >= (1 - s)(d(0) - xi), so a new
//     CCD started from the configuration reached at (a fraction of) t* returns t* > 0 again
//     and successive cut steps converge to the contact instead of stalling at 0.
//   - If max_iterations is reached (grazing or sliding motion much longer than the gap),
//     the time reached so far is returned: conservative, possibly early.
// Optional arguments: conservative_rescaling s in (0, 1) and max_iterations (defaults in
// ccd_parameters.hpp). t_max <= 0 returns 0.
// The caller (the IPC line search, src/nonlinear/) caps the Newton step at
// min(1, 0.8 t*) over all candidate pairs and ranks; this file does not.
#pragma once
#include <cmath>

#include "contact/ccd/additive_ccd.hpp"
#include "contact/ccd/ccd_parameters.hpp"
#include "math/host_device.hpp"
#include "math/vector3.hpp"

namespace dipc::contact {

// Stacked forms: x_t0, x_t1 are 12 doubles [p, t0, t1, t2] (point-triangle) or
// [ea0, ea1, eb0, eb1] (edge-edge); the result carries the iteration count for diagnostics.
DIPC_HD ccd::AdditiveCcdResult point_triangle_ccd(const double x_t0[12], const double x_t1[12], double min_separation,
                                                  double t_max,
                                                  double conservative_rescaling = ccd_defaults::conservative_rescaling,
                                                  int max_iterations = ccd_defaults::max_iterations) {
  return ccd::additive_ccd<ccd::PointTrianglePair>(x_t0, x_t1, min_separation, t_max, conservative_rescaling,
                                                   max_iterations);
}

DIPC_HD ccd::AdditiveCcdResult edge_edge_ccd(const double x_t0[12], const double x_t1[12], double min_separation,
                                             double t_max,
                                             double conservative_rescaling = ccd_defaults::conservative_rescaling,
                                             int max_iterations = ccd_defaults::max_iterations) {
  return ccd::additive_ccd<ccd::EdgeEdgePair>(x_t0, x_t1, min_separation, t_max, conservative_rescaling,
                                              max_iterations);
}

namespace ccd {
DIPC_HD void stack4(const double a[3], const double b[3], const double c[3], const double d[3], double x[12]) {
  for (int k = 0; k < 3; ++k) {
    x[k] = a[k];
    x[3 + k] = b[k];
    x[6 + k] = c[k];
    x[9 + k] = d[k];
  }
}
}  // namespace ccd

DIPC_HD double point_triangle_time_of_impact(const double p_t0[3], const double t0_t0[3], const double t1_t0[3],
                                             const double t2_t0[3], const double p_t1[3], const double t0_t1[3],
                                             const double t1_t1[3], const double t2_t1[3], double min_separation,
                                             double t_max,
                                             double conservative_rescaling = ccd_defaults::conservative_rescaling,
                                             int max_iterations = ccd_defaults::max_iterations) {
  double x_t0[12], x_t1[12];
  ccd::stack4(p_t0, t0_t0, t1_t0, t2_t0, x_t0);
  ccd::stack4(p_t1, t0_t1, t1_t1, t2_t1, x_t1);
  return point_triangle_ccd(x_t0, x_t1, min_separation, t_max, conservative_rescaling, max_iterations).toi;
}

DIPC_HD double edge_edge_time_of_impact(const double ea0_t0[3], const double ea1_t0[3], const double eb0_t0[3],
                                        const double eb1_t0[3], const double ea0_t1[3], const double ea1_t1[3],
                                        const double eb0_t1[3], const double eb1_t1[3], double min_separation,
                                        double t_max,
                                        double conservative_rescaling = ccd_defaults::conservative_rescaling,
                                        int max_iterations = ccd_defaults::max_iterations) {
  double x_t0[12], x_t1[12];
  ccd::stack4(ea0_t0, ea1_t0, eb0_t0, eb1_t0, x_t0);
  ccd::stack4(ea0_t1, ea1_t1, eb0_t1, eb1_t1, x_t1);
  return edge_edge_ccd(x_t0, x_t1, min_separation, t_max, conservative_rescaling, max_iterations).toi;
}

// A point moving against a static plane (analytic obstacle) through plane_origin with normal
// plane_normal (any nonzero length). The distance is unsigned, |n.(p - o)| / |n|, so a point
// starting on either side is handled; it changes linearly in t, so the time it reaches xi is
// known in closed form, t = (s0 - xi) / (s0 - s1), with s0, s1 the distances at t = 0 and 1
// on the starting side. To stay conservative for the exact values of the given coordinates,
// s0 is lowered and s0 - s1 raised by a bound on their rounding error (8 ulps of
// sum_k |n_k (p_k - o_k)| / |n|, Higham, "Accuracy and Stability of Numerical Algorithms",
// 2002, sec. 3.1, dot products), and the quotient by a few ulps. A starting gap below that
// error counts as contact (t* = 0); a zero normal returns 0 (no plane: refuse to move).
DIPC_HD double point_plane_time_of_impact(const double p_t0[3], const double p_t1[3], const double plane_origin[3],
                                          const double plane_normal[3], double min_separation, double t_max) {
  constexpr double eps = ccd_defaults::machine_epsilon;
  if (!(t_max > 0.0)) return 0.0;
  const double nn = dot3(plane_normal, plane_normal);
  if (!(nn > 0.0)) return 0.0;
  const double inv_norm = 1.0 / sqrt(nn);
  double w0[3], w1[3];
  subtract3(p_t0, plane_origin, w0);
  subtract3(p_t1, plane_origin, w1);
  double s0 = dot3(plane_normal, w0) * inv_norm;
  double s1 = dot3(plane_normal, w1) * inv_norm;
  double a0 = 0.0, a1 = 0.0;
  for (int k = 0; k < 3; ++k) {
    a0 += fabs(plane_normal[k] * w0[k]);
    a1 += fabs(plane_normal[k] * w1[k]);
  }
  const double err0 = 8.0 * eps * a0 * inv_norm, err1 = 8.0 * eps * a1 * inv_norm;
  if (s0 < 0.0) {
    s0 = -s0;
    s1 = -s1;
  }
  const double gap = s0 - err0 - min_separation;  // lower bound of the starting gap
  if (!(gap > 0.0)) return 0.0;
  const double closing = s0 - s1 + err0 + err1;  // upper bound of the approach per unit t
  if (!(closing > 0.0)) return t_max;            // certainly receding
  const double t = gap / closing * (1.0 - 4.0 * eps);
  return t < t_max ? t : t_max;
}

}  // namespace dipc::contact
