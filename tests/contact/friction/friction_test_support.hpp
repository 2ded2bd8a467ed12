// Shared helpers for the friction tests: seeded random geometry, central finite differences,
// and closest-point coordinates computed by an algorithm independent of the code under test
// (interior stationary point, else the best boundary candidate, instead of Voronoi-region
// classification).
#pragma once
#include <array>
#include <cmath>
#include <functional>
#include <random>
#include <vector>

#include "support/finite_difference.hpp"

namespace dipc::test {

// A 3-vector whose arithmetic operators are found by argument-dependent lookup.
struct Vec3 {
  double c[3];
  double& operator[](int i) { return c[i]; }
  double operator[](int i) const { return c[i]; }
  double* data() { return c; }
  const double* data() const { return c; }
};

inline double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline Vec3 operator-(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
inline Vec3 operator+(const Vec3& a, const Vec3& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
inline Vec3 operator*(double s, const Vec3& a) { return {s * a[0], s * a[1], s * a[2]}; }
inline Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
inline double norm(const Vec3& a) { return std::sqrt(dot(a, a)); }
inline Vec3 normalized(const Vec3& a) { return (1.0 / norm(a)) * a; }

inline Vec3 random_vec3(std::mt19937_64& rng, double lo = -1.0, double hi = 1.0) {
  std::uniform_real_distribution<double> u(lo, hi);
  return {u(rng), u(rng), u(rng)};
}

inline std::array<double, 12> stack(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  return {a[0], a[1], a[2], b[0], b[1], b[2], c[0], c[1], c[2], d[0], d[1], d[2]};
}

inline Vec3 point_of(const double* x) { return {x[0], x[1], x[2]}; }

// Parameter of the point of segment [a,b] closest to p (clamped projection).
inline double reference_segment_parameter(const Vec3& p, const Vec3& a, const Vec3& b) {
  const double l2 = dot(b - a, b - a);
  if (l2 == 0.0) return 0.0;
  const double s = dot(p - a, b - a) / l2;
  return s < 0 ? 0.0 : (s > 1 ? 1.0 : s);
}

// Barycentric (beta1, beta2) of the closest point of a triangle: the plane projection when it
// falls inside, otherwise the nearest of the three edge projections.
inline std::array<double, 2> reference_point_triangle(const Vec3& p, const Vec3& t0, const Vec3& t1, const Vec3& t2) {
  const Vec3 e1 = t1 - t0, e2 = t2 - t0, r = p - t0;
  const double a = dot(e1, e1), b = dot(e1, e2), c = dot(e2, e2), f1 = dot(r, e1), f2 = dot(r, e2);
  const double det = a * c - b * b;
  const double b1 = (c * f1 - b * f2) / det, b2 = (a * f2 - b * f1) / det;
  if (b1 >= 0 && b2 >= 0 && b1 + b2 <= 1) return {b1, b2};
  std::array<double, 2> best{};
  double best_d = INFINITY;
  const auto consider = [&](double c1, double c2) {
    const Vec3 q = t0 + c1 * e1 + c2 * e2;
    const double d = dot(p - q, p - q);
    if (d < best_d) {
      best_d = d;
      best = {c1, c2};
    }
  };
  const double s01 = reference_segment_parameter(p, t0, t1);
  const double s02 = reference_segment_parameter(p, t0, t2);
  const double s12 = reference_segment_parameter(p, t1, t2);
  consider(s01, 0);
  consider(0, s02);
  consider(1 - s12, s12);
  return best;
}

// (alpha, beta) of the closest points of two segments: the interior stationary point when it
// lies in [0,1]^2, otherwise the best of the four endpoint-against-segment candidates.
inline std::array<double, 2> reference_edge_edge(const Vec3& a0, const Vec3& a1, const Vec3& b0, const Vec3& b1) {
  const Vec3 ea = a1 - a0, eb = b1 - b0, r = a0 - b0;
  const double A = dot(ea, ea), B = dot(ea, eb), C = dot(eb, eb), D = dot(ea, r), E = dot(eb, r);
  const double det = A * C - B * B;
  if (det > 1e-12 * A * C) {
    const double s = (B * E - C * D) / det, t = (A * E - B * D) / det;
    if (s >= 0 && s <= 1 && t >= 0 && t <= 1) return {s, t};
  }
  std::array<double, 2> best{};
  double best_d = INFINITY;
  const auto consider = [&](double s, double t) {
    const Vec3 d = (a0 + s * ea) - (b0 + t * eb);
    if (dot(d, d) < best_d) {
      best_d = dot(d, d);
      best = {s, t};
    }
  };
  consider(0, reference_segment_parameter(a0, b0, b1));
  consider(1, reference_segment_parameter(a1, b0, b1));
  consider(reference_segment_parameter(b0, a0, a1), 0);
  consider(reference_segment_parameter(b1, a0, a1), 1);
  return best;
}

inline double max_abs(const double* a, int n) {
  double m = 0;
  for (int i = 0; i < n; ++i) m = std::fmax(m, std::fabs(a[i]));
  return m;
}

inline double max_abs_diff(const double* a, const double* b, int n) {
  double m = 0;
  for (int i = 0; i < n; ++i) m = std::fmax(m, std::fabs(a[i] - b[i]));
  return m;
}

}  // namespace dipc::test
