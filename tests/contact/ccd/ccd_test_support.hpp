// Shared helpers for the CCD tests: stacked 4-vertex configurations, linear trajectories,
// brute-force sampling of the distance along a trajectory, and the bound on t* that additive
// CCD guarantees when the gap closes at a constant rate (time_of_impact.hpp).
#pragma once
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>

#include "contact/ccd/ccd_distances.hpp"
#include "contact/ccd/ccd_parameters.hpp"
#include "contact/ccd/time_of_impact.hpp"

namespace dipc::test {

using Vec3 = std::array<double, 3>;
using Stack = std::array<double, 12>;

enum class PairKind { point_triangle, edge_edge };

inline Stack stack(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  return {a[0], a[1], a[2], b[0], b[1], b[2], c[0], c[1], c[2], d[0], d[1], d[2]};
}

inline Stack translated(const Stack& x, const Vec3& v) {
  Stack y = x;
  for (int i = 0; i < 12; ++i) y[i] += v[i % 3];
  return y;
}

inline Stack scaled(const Stack& x, double factor) {
  Stack y = x;
  for (double& v : y) v *= factor;
  return y;
}

inline Stack lerp(const Stack& a, const Stack& b, double t) {
  Stack x;
  for (int i = 0; i < 12; ++i) x[i] = a[i] + t * (b[i] - a[i]);
  return x;
}

inline double pair_distance(PairKind kind, const Stack& x) {
  const double* v = x.data();
  const double d2 = kind == PairKind::point_triangle
                        ? contact::ccd::point_triangle_distance_squared(v, v + 3, v + 6, v + 9)
                        : contact::ccd::edge_edge_distance_squared(v, v + 3, v + 6, v + 9);
  return std::sqrt(d2);
}

inline double distance_at(PairKind kind, const Stack& a, const Stack& b, double t) {
  return pair_distance(kind, lerp(a, b, t));
}

inline contact::ccd::AdditiveCcdResult run_ccd(PairKind kind, const Stack& a, const Stack& b, double min_separation,
                                               double t_max = 1.0,
                                               double s = contact::ccd_defaults::conservative_rescaling,
                                               int max_iterations = contact::ccd_defaults::max_iterations) {
  return kind == PairKind::point_triangle
             ? contact::point_triangle_ccd(a.data(), b.data(), min_separation, t_max, s, max_iterations)
             : contact::edge_edge_ccd(a.data(), b.data(), min_separation, t_max, s, max_iterations);
}

// First of n + 1 uniform samples of [t_begin, t_end] at which the distance is <= xi, or
// +infinity if none is.
inline double first_sampled_contact(PairKind kind, const Stack& a, const Stack& b, double xi, double t_begin,
                                    double t_end, int n) {
  for (int i = 0; i <= n; ++i) {
    const double t = t_begin + (t_end - t_begin) * i / n;
    if (distance_at(kind, a, b, t) <= xi) return t;
  }
  return std::numeric_limits<double>::infinity();
}

inline double min_sampled_distance(PairKind kind, const Stack& a, const Stack& b, double t_begin, double t_end, int n) {
  double best = std::numeric_limits<double>::infinity();
  for (int i = 0; i <= n; ++i) best = std::fmin(best, distance_at(kind, a, b, t_begin + (t_end - t_begin) * i / n));
  return best;
}

// The contract of t*: the distance stays > xi on [0, t*] (checked on n + 1 samples and at t*).
inline ::testing::AssertionResult collision_free_until(PairKind kind, const Stack& a, const Stack& b, double xi,
                                                       double toi, int n = 4000) {
  for (int i = 0; i <= n; ++i) {
    const double t = toi * i / n;
    const double d = distance_at(kind, a, b, t);
    if (!(d > xi))
      return ::testing::AssertionFailure()
             << "distance " << d << " <= min_separation " << xi << " at t = " << t << " <= t* = " << toi;
  }
  return ::testing::AssertionSuccess();
}

// If the gap d - xi closes at a constant rate r <= l_p, every additive-CCD step shrinks it
// by the same factor q = 1 - s r / l_p >= 1 - s, and the iteration stops after the first k
// steps with q^k >= 1 - s (k >= 1), so t*/tau = 1 - q^k > 1 - sqrt(1 - s): either k = 1 and
// q < sqrt(1 - s), or q^k < (1 - s) / q <= sqrt(1 - s).
inline double linear_approach_lower_bound(double s = contact::ccd_defaults::conservative_rescaling) {
  return 1.0 - std::sqrt(1.0 - s);
}

}  // namespace dipc::test
