// Additive CCD (Li, Kaufman and Jiang 2021, "Codimensional Incremental Potential Contact",
// ACM TOG 40(4), sec. 5 "Additive CCD", Algorithm 1): the conservative time-of-impact
// iteration shared by the point-triangle and edge-edge narrow phase (time_of_impact.hpp).
//
// Idea. Let d(t) be the unsigned distance between the two primitives on the linear
// trajectory x(t) = x0 + t dx. If every point of the first primitive moves relative to every
// point of the second by at most l_p per unit t, then |d'(t)| <= l_p, so d stays above xi for
// t < (d(t0) - xi) / l_p after any t0. The iteration advances by s times that certified
// step, re-measures d, and stops once the gap d - xi has fallen below (1 - s) times its
// initial value, returning the last time reached before that measurement. Everything it
// returns is therefore certified collision-free in exact arithmetic, and at the returned time
// the gap is still at least (1 - s)(d0 - xi), so re-running from the configuration reached
// there (or from any earlier point) makes progress instead of collapsing to 0.
//
// Motion bound. The paper subtracts the mean displacement and uses
// l_p = max ||dx_i|| over one primitive + max ||dx_j|| over the other. Here l_p is
// max_{i,j} ||dx_i - dx_j|| over vertex pairs (i in the first primitive, j in the second):
// a point of the first primitive moves by sum_i a_i dx_i and one of the second by
// sum_j b_j dx_j (barycentric weights), whose difference sum_ij a_i b_j (dx_i - dx_j) has
// norm at most that maximum. It is a valid Lipschitz bound, invariant to a common
// translation, and never larger than the paper's: |dx_i - dx_j| <= |dx_i - c| + |dx_j - c|
// for the mean displacement c. A tighter bound means longer steps and earlier exits.
#pragma once
#include <cmath>

#include "contact/ccd/ccd_distances.hpp"
#include "contact/ccd/ccd_parameters.hpp"
#include "math/host_device.hpp"
#include "math/vector3.hpp"

namespace dipc::contact::ccd {

struct AdditiveCcdResult {
  double toi;      // t*: collision-free (distance > xi) on [0, toi]; t_max when no impact
  int iterations;  // distance evaluations after the initial one
  bool truncated;  // stopped by the max_iterations guard (toi is still conservative)
};

// A point-triangle pair on stacked coordinates [p, t0, t1, t2].
struct PointTrianglePair {
  static DIPC_HD double distance_squared(const double x[12]) {
    return point_triangle_distance_squared(x, x + 3, x + 6, x + 9);
  }
  static DIPC_HD double motion_bound_squared(const double dx[12]) {
    double worst = 0.0;
    for (int j = 1; j < 4; ++j) {
      double r[3];
      subtract3(dx, dx + 3 * j, r);
      const double rr = dot3(r, r);
      worst = rr > worst ? rr : worst;
    }
    return worst;
  }
};

// An edge-edge pair on stacked coordinates [ea0, ea1, eb0, eb1].
struct EdgeEdgePair {
  static DIPC_HD double distance_squared(const double x[12]) {
    return edge_edge_distance_squared(x, x + 3, x + 6, x + 9);
  }
  static DIPC_HD double motion_bound_squared(const double dx[12]) {
    double worst = 0.0;
    for (int i = 0; i < 2; ++i)
      for (int j = 2; j < 4; ++j) {
        double r[3];
        subtract3(dx + 3 * i, dx + 3 * j, r);
        const double rr = dot3(r, r);
        worst = rr > worst ? rr : worst;
      }
    return worst;
  }
};

// Conservative time of impact of a pair whose 4 vertices move linearly from x_t0 to x_t1
// (stacked, 12 doubles each). See time_of_impact.hpp for the contract.
template <class Pair>
DIPC_HD AdditiveCcdResult additive_ccd(const double x_t0[12], const double x_t1[12], double min_separation,
                                       double t_max, double conservative_rescaling, int max_iterations) {
  if (!(t_max > 0.0)) return {0.0, 0, false};

  // Distances are translation invariant: work relative to the mean start position and the
  // mean displacement, so that a large common offset or translation does not cost precision
  // in x0 + t dx.
  double c0[3] = {0.0, 0.0, 0.0}, cd[3] = {0.0, 0.0, 0.0};
  double magnitude = 0.0;  // largest |coordinate|, for the resolution limit
  for (int v = 0; v < 4; ++v)
    for (int k = 0; k < 3; ++k) {
      c0[k] += 0.25 * x_t0[3 * v + k];
      cd[k] += 0.25 * (x_t1[3 * v + k] - x_t0[3 * v + k]);
      const double m0 = fabs(x_t0[3 * v + k]), m1 = fabs(x_t1[3 * v + k]);
      magnitude = m0 > magnitude ? m0 : magnitude;
      magnitude = m1 > magnitude ? m1 : magnitude;
    }
  const double resolution = ccd_defaults::resolution_ulps * ccd_defaults::machine_epsilon * magnitude;
  double x0[12], dx[12];
  for (int v = 0; v < 4; ++v)
    for (int k = 0; k < 3; ++k) {
      x0[3 * v + k] = x_t0[3 * v + k] - c0[k];
      dx[3 * v + k] = (x_t1[3 * v + k] - x_t0[3 * v + k]) - cd[k];
    }

  const double xi = min_separation;
  const double s = conservative_rescaling;
  double d = sqrt(Pair::distance_squared(x0));
  if (!(d - xi > resolution)) return {0.0, 0, false};
  const double l_p = sqrt(Pair::motion_bound_squared(dx));
  if (!(l_p > 0.0)) return {t_max, 0, false};  // no relative motion: d is constant

  const double gap = (1.0 - s) * (d - xi);
  double t = 0.0;
  for (int it = 1; it <= max_iterations; ++it) {
    const double step = s * (d - xi) / l_p;
    // [t, t + step] is certified collision-free by the bound |d'| <= l_p.
    if (t + step >= t_max) return {t_max, it - 1, false};
    const double t_next = t + step;
    double x[12];
    for (int i = 0; i < 12; ++i) x[i] = x0[i] + t_next * dx[i];
    d = sqrt(Pair::distance_squared(x));
    // d - xi <= resolution cannot happen in exact arithmetic unless the initial gap was
    // within about 1 / (1 - s) of the resolution (each step keeps a fraction 1 - s of it);
    // then stop at the last certified time. Otherwise the first step is always kept, so
    // the result is at least s (d0 - xi) / l_p > 0 (or t_max).
    if (!(d - xi > resolution)) return {t, it, false};
    if (t > 0.0 && d - xi < gap) return {t, it, false};
    t = t_next;
  }
  return {t, max_iterations, true};
}

}  // namespace dipc::contact::ccd
