// Shared helpers for the contact geometry tests: small vector arithmetic on std::array,
// seeded random configurations (point-triangle and edge-edge) forced into a chosen
// closest-feature type by construction, and central finite-difference checks of
// value -> gradient -> Hessian. Independent of the code under test: configurations are
// built from the closest points and KKT sign conditions, not from the classifiers.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <random>
#include <vector>

#include "support/finite_difference.hpp"

namespace dipc::contact::test {

using Vec3 = std::array<double, 3>;

inline Vec3 operator+(const Vec3& a, const Vec3& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
inline Vec3 operator-(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
inline Vec3 operator*(double s, const Vec3& a) { return {s * a[0], s * a[1], s * a[2]}; }
inline double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
inline double norm(const Vec3& a) { return std::sqrt(dot(a, a)); }
inline Vec3 normalized(const Vec3& a) { return (1.0 / norm(a)) * a; }

inline Vec3 random_unit(std::mt19937_64& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  Vec3 v;
  do {
    v = {n(rng), n(rng), n(rng)};
  } while (norm(v) < 1e-3);
  return normalized(v);
}

// A random unit vector orthogonal to the unit vector m.
inline Vec3 random_orthogonal_unit(std::mt19937_64& rng, const Vec3& m) {
  Vec3 v;
  do {
    const Vec3 r = random_unit(rng);
    v = r - dot(r, m) * m;
  } while (norm(v) < 1e-2);
  return normalized(v);
}

inline double uniform(std::mt19937_64& rng, double lo, double hi) {
  return std::uniform_real_distribution<double>(lo, hi)(rng);
}

// Four stacked vertices: [p, t0, t1, t2] or [ea0, ea1, eb0, eb1].
struct Stencil {
  std::array<Vec3, 4> x;
  const double* operator[](int i) const { return x[i].data(); }
  std::array<double, 12> flat() const {
    std::array<double, 12> f;
    for (int i = 0; i < 12; ++i) f[i] = x[i / 3][i % 3];
    return f;
  }
  static Stencil from_flat(const double* f) {
    Stencil s;
    for (int i = 0; i < 12; ++i) s.x[i / 3][i % 3] = f[i];
    return s;
  }
  // x -> scale x + offset, for checking every length scale with the same shapes.
  Stencil scaled(double scale, const Vec3& offset) const {
    Stencil s;
    for (int i = 0; i < 4; ++i) s.x[i] = scale * x[i] + offset;
    return s;
  }
  double longest_extent() const {
    double l = 0.0;
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j) l = std::max(l, norm(x[i] - x[j]));
    return l;
  }
};

// Unit-size triangle with all angles above ~15 degrees, randomly placed and oriented.
inline std::array<Vec3, 3> random_triangle(std::mt19937_64& rng) {
  for (;;) {
    std::array<Vec3, 3> t;
    for (auto& v : t) v = {uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1)};
    bool good = true;
    for (int i = 0; i < 3 && good; ++i) {
      const Vec3 a = t[(i + 1) % 3] - t[i], b = t[(i + 2) % 3] - t[i];
      good = norm(a) > 0.3 && norm(cross(a, b)) > std::sin(0.26) * norm(a) * norm(b);
    }
    if (good) return t;
  }
}

// Point-triangle stencil whose closest feature is `type` (0..2 vertex t_i, 3..5 edge
// E_{type-3} = t_i t_{i+1}, 6 face), built in the Voronoi region of that feature: the
// face prism, the edge slab beyond its outward in-plane normal, or the vertex wedge between
// the outward normals of its two edges. `height` is the signed offset along the normal.
inline Stencil point_triangle_of_type(std::mt19937_64& rng, int type, double height) {
  const auto t = random_triangle(rng);
  const Vec3 n = normalized(cross(t[1] - t[0], t[2] - t[0]));
  // Outward in-plane normal of edge i (t_i -> t_{i+1}): for counter-clockwise vertices
  // about n, edge x n points away from the opposite vertex.
  auto outward = [&](int i) { return normalized(cross(t[(i + 1) % 3] - t[i], n)); };
  Vec3 in_plane;
  if (type == 6) {
    double b1, b2;
    do {
      b1 = uniform(rng, 0.1, 0.8);
      b2 = uniform(rng, 0.1, 0.8);
    } while (b1 + b2 > 0.9);
    in_plane = t[0] + b1 * (t[1] - t[0]) + b2 * (t[2] - t[0]);
  } else if (type >= 3) {
    const int i = type - 3;
    in_plane = t[i] + uniform(rng, 0.1, 0.9) * (t[(i + 1) % 3] - t[i]) + uniform(rng, 0.05, 1.0) * outward(i);
  } else {
    const int i = type;
    const double lambda = uniform(rng, 0.1, 0.9);
    const Vec3 wedge = lambda * outward(i) + (1.0 - lambda) * outward((i + 2) % 3);
    in_plane = t[i] + uniform(rng, 0.05, 1.0) * normalized(wedge);
  }
  return Stencil{{in_plane + height * n, t[0], t[1], t[2]}};
}

// Direction into a segment from its closest endpoint: positive component along `away`
// (the endpoint minus the other closest point), which is the KKT sign condition that makes
// the endpoint the minimiser.
inline Vec3 direction_away(std::mt19937_64& rng, const Vec3& away) {
  const double phi = uniform(rng, 0.0, 1.35);
  return normalized(std::cos(phi) * away + std::sin(phi) * random_orthogonal_unit(rng, away));
}

// Edge-edge stencil [ea0, ea1, eb0, eb1] whose closest features are feature_a / feature_b
// (0 start, 1 end, 2 interior) at squared distance separation^2: closest points pa, pb with
// pa - pb = separation m; an interior closest point has its edge orthogonal to m, an
// endpoint has its edge leaving along a direction with positive component along
// (endpoint - other closest point). Both edges interior are kept at least ~15 degrees apart.
inline Stencil edge_edge_of_features(std::mt19937_64& rng, int feature_a, int feature_b, double separation) {
  const Vec3 m = random_unit(rng);
  const Vec3 pb = {uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1)};
  const Vec3 pa = pb + separation * m;
  auto make_edge = [&](const Vec3& p, int feature, const Vec3& away, const Vec3* avoid) {
    const double length = uniform(rng, 0.5, 2.0);
    std::array<Vec3, 2> e;
    if (feature == 2) {
      Vec3 u;
      do {
        u = random_orthogonal_unit(rng, m);
      } while (avoid && norm(cross(u, *avoid)) < 0.26);
      const double s = uniform(rng, 0.1, 0.9);
      e = {p - s * length * u, p + (1.0 - s) * length * u};
    } else {
      const Vec3 d = direction_away(rng, away);
      e[feature] = p;
      e[1 - feature] = p + length * d;
    }
    return e;
  };
  const auto a = make_edge(pa, feature_a, m, nullptr);
  const Vec3 ua = normalized(a[1] - a[0]);
  const auto b = make_edge(pb, feature_b, -1.0 * m, feature_a == 2 ? &ua : nullptr);
  return Stencil{{a[0], a[1], b[0], b[1]}};
}

// Features (A, B) of each EdgeEdgeType value, in enum order.
inline constexpr int kEdgeEdgeFeatures[9][2] = {{0, 0}, {0, 1}, {1, 0}, {1, 1}, {2, 0}, {2, 1}, {0, 2}, {1, 2}, {2, 2}};

// Central differences of a function of the 12 stacked dofs against its gradient and of the
// gradient against the Hessian, with step h. Errors are measured in the max norm relative
// to the largest entry of the analytic derivative (plus an absolute floor for derivatives
// that vanish), so a wrong sign or factor on any non-negligible block fails.
struct Derivatives {
  std::function<double(const double*)> value;
  std::function<void(const double*, double*)> gradient;
  std::function<void(const double*, double*)> hessian;
};

inline double max_abs(const double* a, int n) {
  double m = 0.0;
  for (int i = 0; i < n; ++i) m = std::max(m, std::abs(a[i]));
  return m;
}

struct FiniteDifferenceErrors {
  double gradient;   // relative max-norm error of the gradient
  double hessian;    // relative max-norm error of the Hessian
  double asymmetry;  // max |H - H^T| relative to max |H|
};

inline FiniteDifferenceErrors finite_difference_errors(const Derivatives& f, const double* x0, double h,
                                                       double gradient_floor, double hessian_floor) {
  double g[12], H[144], g_fd[12], H_fd[144];
  f.gradient(x0, g);
  f.hessian(x0, H);
  dipc::test::central_difference([&f](const double* x, double* value) { *value = f.value(x); }, x0, 12, 1, h, g_fd);
  dipc::test::central_difference(f.gradient, x0, 12, 12, h, H_fd);
  double eg = 0.0, eh = 0.0, asym = 0.0;
  for (int i = 0; i < 12; ++i) eg = std::max(eg, std::abs(g[i] - g_fd[i]));
  for (int i = 0; i < 144; ++i) eh = std::max(eh, std::abs(H[i] - H_fd[i]));
  for (int i = 0; i < 12; ++i)
    for (int j = 0; j < 12; ++j) asym = std::max(asym, std::abs(H[12 * i + j] - H[12 * j + i]));
  const double gs = std::max(max_abs(g, 12), gradient_floor);
  const double hs = std::max(max_abs(H, 144), hessian_floor);
  return {eg / gs, eh / hs, asym / hs};
}

}  // namespace dipc::contact::test

namespace dipc::contact::test {

// Reference distances by an algorithm independent of the classifiers: the minimiser is
// either interior (the critical point of the unconstrained quadratic, found from the 2x2
// normal equations, kept if it lies inside) or on the boundary (point-segment distances
// with a clamped projection). Long double for headroom.
inline long double point_segment_squared(const Vec3& p, const Vec3& a, const Vec3& b) {
  long double r[3], e[3], re = 0, ee = 0;
  for (int i = 0; i < 3; ++i) {
    r[i] = (long double)p[i] - a[i];
    e[i] = (long double)b[i] - a[i];
    re += r[i] * e[i];
    ee += e[i] * e[i];
  }
  const long double tau = ee > 0 ? std::clamp(re / ee, (long double)0, (long double)1) : 0;
  long double d = 0;
  for (int i = 0; i < 3; ++i) d += (r[i] - tau * e[i]) * (r[i] - tau * e[i]);
  return d;
}

// Critical point (alpha, beta) of |r + alpha ea + beta eb|^2, from the normal equations
// [ea.ea, ea.eb; ea.eb, eb.eb] (alpha, beta) = -(ea.r, eb.r); false when ea, eb are parallel.
inline bool interior_critical_point(const Vec3& r_, const Vec3& ea_, const Vec3& eb_, long double* alpha,
                                    long double* beta) {
  long double r[3], ea[3], eb[3];
  for (int i = 0; i < 3; ++i) {
    r[i] = r_[i];
    ea[i] = ea_[i];
    eb[i] = eb_[i];
  }
  auto d = [](const long double* u, const long double* v) { return u[0] * v[0] + u[1] * v[1] + u[2] * v[2]; };
  const long double a = d(ea, ea), b = d(ea, eb), c = d(eb, eb), e = d(ea, r), f = d(eb, r);
  const long double det = a * c - b * b;
  if (det <= 1e-24L * a * c) return false;
  *alpha = (b * f - c * e) / det;
  *beta = (b * e - a * f) / det;
  return true;
}

inline double reference_point_triangle(const Stencil& s) {
  const Vec3 &p = s.x[0], &t0 = s.x[1], &t1 = s.x[2], &t2 = s.x[3];
  long double best = std::min(
      {point_segment_squared(p, t0, t1), point_segment_squared(p, t1, t2), point_segment_squared(p, t2, t0)});
  // Minimise |t0 + alpha (t1 - t0) + beta (t2 - t0) - p|^2 over the plane, keep it if inside.
  long double alpha, beta;
  if (interior_critical_point(t0 - p, t1 - t0, t2 - t0, &alpha, &beta) && alpha >= 0 && beta >= 0 &&
      alpha + beta <= 1) {
    long double d = 0;
    for (int i = 0; i < 3; ++i) {
      const long double q = t0[i] + alpha * ((long double)t1[i] - t0[i]) + beta * ((long double)t2[i] - t0[i]);
      d += (q - p[i]) * (q - p[i]);
    }
    best = std::min(best, d);
  }
  return (double)best;
}

inline double reference_edge_edge(const Stencil& s) {
  const Vec3 &a0 = s.x[0], &a1 = s.x[1], &b0 = s.x[2], &b1 = s.x[3];
  long double best = std::min({point_segment_squared(a0, b0, b1), point_segment_squared(a1, b0, b1),
                               point_segment_squared(b0, a0, a1), point_segment_squared(b1, a0, a1)});
  // |a0 + alpha (a1 - a0) - b0 - beta (b1 - b0)|^2 over both lines, kept if inside both.
  long double alpha, beta;
  if (interior_critical_point(a0 - b0, a1 - a0, b0 - b1, &alpha, &beta) && alpha >= 0 && alpha <= 1 && beta >= 0 &&
      beta <= 1) {
    long double d = 0;
    for (int i = 0; i < 3; ++i) {
      const long double pa = a0[i] + alpha * ((long double)a1[i] - a0[i]);
      const long double pb = b0[i] + beta * ((long double)b1[i] - b0[i]);
      d += (pa - pb) * (pa - pb);
    }
    best = std::min(best, d);
  }
  return (double)best;
}

// Brute-force minima over a uniform barycentric sampling (n intervals per edge). Every
// point of the triangle or segment lies within `spacing` of a sample, so the true minimum
// distance D satisfies sqrt(brute) - spacing <= sqrt(D) <= sqrt(brute).
inline double brute_force_point_triangle(const Stencil& s, int n, double* spacing) {
  const Vec3 &p = s.x[0], &t0 = s.x[1], &t1 = s.x[2], &t2 = s.x[3];
  double best = INFINITY;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; i + j <= n; ++j) {
      const double a = double(i) / n, b = double(j) / n;
      const Vec3 q = t0 + a * (t1 - t0) + b * (t2 - t0);
      best = std::min(best, dot(q - p, q - p));
    }
  *spacing = (norm(t1 - t0) + norm(t2 - t0)) / n;
  return best;
}

inline double brute_force_edge_edge(const Stencil& s, int n, double* spacing) {
  const Vec3 &a0 = s.x[0], &a1 = s.x[1], &b0 = s.x[2], &b1 = s.x[3];
  std::vector<Vec3> sb(n + 1);
  for (int j = 0; j <= n; ++j) sb[j] = b0 + (double(j) / n) * (b1 - b0);
  double best = INFINITY;
  for (int i = 0; i <= n; ++i) {
    const Vec3 pa = a0 + (double(i) / n) * (a1 - a0);
    for (const Vec3& pb : sb) best = std::min(best, dot(pa - pb, pa - pb));
  }
  *spacing = 0.5 * (norm(a1 - a0) + norm(b1 - b0)) / n;
  return best;
}

}  // namespace dipc::contact::test
