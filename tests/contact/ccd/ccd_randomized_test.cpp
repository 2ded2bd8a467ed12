// Randomized conformance of the point-triangle and edge-edge CCD: 10^5 random linear
// trajectories per pair type (general, coplanar, parallel, starting close, forced crossings,
// degenerate primitives, grazing crossings; lengths from 1e-4 to 1e4), each compared with a dense sampling of
// the distance along the trajectory. Sampling can miss a contact, but a sampled distance
// <= min_separation at time tau is a contact, so t* <= tau is required, and so is t* <= the
// crossing time built into the "crossing" family: zero false negatives. False positives
// (t* < 0.5 tau, or t* < t_max although no sample comes within 1e-3 of the scale of
// min_separation) are counted and printed per family: additive CCD produces them by design.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>

#include "ccd_test_support.hpp"

namespace {

using namespace dipc::test;
namespace defaults = dipc::contact::ccd_defaults;

struct Trajectory {
  Stack a, b;
  double xi, t_max, scale;
  double known_contact;  // crossing time built into the "crossing" family, else +infinity
};

class TrajectoryGenerator {
 public:
  TrajectoryGenerator(PairKind kind, std::uint64_t seed) : kind_(kind), rng_(seed) {}

  Trajectory next(int family) {
    Stack a, b;
    double known_contact = std::numeric_limits<double>::infinity();
    for (double& v : a) v = u();
    const double motion = std::pow(10.0, u());  // 0.1 .. 10 times the primitive size
    for (int i = 0; i < 12; ++i) b[i] = a[i] + motion * u();
    switch (family) {
      case 1:  // coplanar motion: everything stays in z = 0
        for (int v = 0; v < 4; ++v) a[3 * v + 2] = b[3 * v + 2] = 0.0;
        break;
      case 2:  // parallel: PT moves parallel to the triangle, EE edges parallel, translating
        make_parallel(a, b);
        break;
      case 3:  // starting close: gap 1e-6 .. 1e-2 at t = 0
        make_close_start(a, b);
        break;
      case 4:  // forced crossing at a random time in (0, 1)
        known_contact = make_crossing(a, b);
        break;
      case 6:  // grazing crossing: nearly parallel edges / a point skimming the face
        known_contact = make_grazing_crossing(a, b);
        break;
      case 5:  // degenerate: collinear triangle / zero-length edge
        for (int k = 0; k < 3; ++k) {
          a[9 + k] = 0.5 * (a[3 + k] + a[6 + k]);
          b[9 + k] = 0.5 * (b[3 + k] + b[6 + k]);
        }
        break;
      default: break;
    }
    const double scale = std::pow(10.0, 4.0 * u());
    const Vec3 offset{3 * u() * scale, 3 * u() * scale, 3 * u() * scale};
    const double xi_choices[4] = {0.0, 1e-3, 1e-2, 5e-2};
    Trajectory t;
    t.a = translated(scaled(a, scale), offset);
    t.b = translated(scaled(b, scale), offset);
    t.xi = xi_choices[index(4)] * scale;
    t.t_max = index(4) == 0 ? 0.6 : 1.0;
    t.scale = scale;
    t.known_contact = known_contact;
    return t;
  }

 private:
  double u() { return dist_(rng_); }
  int index(int n) { return int(std::uniform_int_distribution<int>(0, n - 1)(rng_)); }

  void make_parallel(Stack& a, Stack& b) {
    if (kind_ == PairKind::point_triangle) {
      // Triangle in z = 0 translating in-plane, point at a fixed height moving in-plane.
      const double h = 0.1 * u();
      const double shift[2] = {u(), u()};
      for (int v = 0; v < 4; ++v) {
        a[3 * v + 2] = b[3 * v + 2] = v == 0 ? h : 0.0;
        if (v > 0)
          for (int k = 0; k < 2; ++k) b[3 * v + k] = a[3 * v + k] + shift[k];
      }
    } else {
      // eb parallel to ea, both translating.
      const double len = 0.3 + u();
      for (int k = 0; k < 3; ++k) a[9 + k] = a[6 + k] + len * (a[3 + k] - a[k]);
      for (int e = 0; e < 2; ++e)
        for (int k = 0; k < 3; ++k) b[6 * e + 3 + k] = a[6 * e + 3 + k] + (b[6 * e + k] - a[6 * e + k]);
    }
  }

  void make_close_start(Stack& a, Stack& b) {
    const double gap = std::pow(10.0, -4.0 + 2.0 * u());
    Vec3 q;  // a point on the second primitive (PT: triangle; EE: edge b)
    const double w0 = 0.5 + 0.5 * u(), w1 = 0.5 * (1 - w0);
    for (int k = 0; k < 3; ++k)
      q[k] = kind_ == PairKind::point_triangle ? w0 * a[3 + k] + w1 * a[6 + k] + (1 - w0 - w1) * a[9 + k]
                                               : w0 * a[6 + k] + (1 - w0) * a[9 + k];
    Vec3 dir{u(), u(), u()};
    const double len = std::sqrt(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]);
    for (int k = 0; k < 3; ++k) {
      const double target = q[k] + gap * dir[k] / len;
      const double move = target - a[k];  // move vertex 0 (the point / ea0) next to q
      a[k] += move;
      b[k] += move;
    }
  }

  double make_crossing(Stack& a, Stack& b) {
    // The point (or a point of ea) passes through a point of the triangle (of eb) at tau.
    const double tau = 0.5 + 0.5 * u();
    Stack m = lerp(a, b, tau);
    const double w0 = 0.5 + 0.5 * u(), w1 = 0.5 * (1 - w0);
    Vec3 q;
    for (int k = 0; k < 3; ++k)
      q[k] = kind_ == PairKind::point_triangle ? w0 * m[3 + k] + w1 * m[6 + k] + (1 - w0 - w1) * m[9 + k]
                                               : w0 * m[6 + k] + (1 - w0) * m[9 + k];
    const double s = kind_ == PairKind::point_triangle ? 0.0 : 0.5 + 0.5 * u();
    Vec3 on_first;  // current point of the first primitive at parameter s, time tau
    for (int k = 0; k < 3; ++k) on_first[k] = (1 - s) * m[k] + s * m[3 + k];
    const int first_vertices = kind_ == PairKind::point_triangle ? 1 : 2;
    for (int v = 0; v < first_vertices; ++v)
      for (int k = 0; k < 3; ++k) {
        const double shift = q[k] - on_first[k];
        a[3 * v + k] += shift;
        b[3 * v + k] += shift;
      }
    return tau;
  }

  Vec3 unit_vector() {
    Vec3 v{u(), u(), u()};
    const double len = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    for (double& c : v) c /= len;
    return v;
  }

  // The primitives meet at tau in an interior point q at an angle of 1e-9 to 1e-1 rad: edge b
  // nearly parallel to edge a, or the point moving nearly parallel to the triangle's plane.
  // Such crossings are where the distance evaluation is ill-conditioned (the closest points
  // of nearly parallel lines, ccd_distances.hpp), so they test its error bound.
  double make_grazing_crossing(Stack& a, Stack& b) {
    const double tau = 0.5 + 0.5 * u();
    const double angle = std::pow(10.0, -5.0 + 4.0 * u());
    const Vec3 d = unit_vector(), r = unit_vector();
    Vec3 n{d[1] * r[2] - d[2] * r[1], d[2] * r[0] - d[0] * r[2], d[0] * r[1] - d[1] * r[0]};
    const double nl = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    for (double& c : n) c /= nl;
    const Vec3 w{d[1] * n[2] - d[2] * n[1], d[2] * n[0] - d[0] * n[2], d[0] * n[1] - d[1] * n[0]};
    const Vec3 q{u(), u(), u()}, common{0.1 * u(), 0.1 * u(), 0.1 * u()};
    Stack at_tau{};  // positions at tau; the first primitive then moves by `common`
    Vec3 relative;   // extra velocity of the moving part (edge b / the point)
    const double speed = std::pow(10.0, -2.0 + 2.0 * u()) * (u() < 0 ? -1.0 : 1.0);
    if (kind_ == PairKind::edge_edge) {
      const double la = 0.5 + 0.5 * u(), lb = 0.5 + 0.5 * u(), sa = 0.5 + 0.4 * u(), sb = 0.5 + 0.4 * u();
      for (int k = 0; k < 3; ++k) {
        const double db = std::cos(angle) * d[k] + std::sin(angle) * w[k];
        at_tau[k] = q[k] - sa * la * d[k];
        at_tau[3 + k] = q[k] + (1 - sa) * la * d[k];
        at_tau[6 + k] = q[k] - sb * lb * db;
        at_tau[9 + k] = q[k] + (1 - sb) * lb * db;
        relative[k] = speed * n[k];
      }
    } else {
      // Triangle in the plane spanned by d and w around q; the point passes through q.
      const double b0 = 0.2 + 0.1 * u(), b1 = 0.2 + 0.1 * u();
      const Vec3 e1{d[0] + 0.3 * w[0], d[1] + 0.3 * w[1], d[2] + 0.3 * w[2]};
      const Vec3 e2{-0.2 * d[0] + w[0], -0.2 * d[1] + w[1], -0.2 * d[2] + w[2]};
      for (int k = 0; k < 3; ++k) {
        const double t0 = q[k] - b0 * e1[k] - b1 * e2[k];  // q = t0 + b0 e1 + b1 e2
        at_tau[3 + k] = t0;
        at_tau[6 + k] = t0 + e1[k];
        at_tau[9 + k] = t0 + e2[k];
        at_tau[k] = q[k];
        relative[k] = speed * (std::cos(angle) * d[k] + std::sin(angle) * n[k]);
      }
    }
    const int first_moving = kind_ == PairKind::edge_edge ? 2 : 0;
    const int last_moving = kind_ == PairKind::edge_edge ? 4 : 1;
    for (int v = 0; v < 4; ++v) {
      const bool moving = v >= first_moving && v < last_moving;
      for (int k = 0; k < 3; ++k) {
        const double velocity = common[k] + (moving ? relative[k] : 0.0);
        a[3 * v + k] = at_tau[3 * v + k] - tau * velocity;
        b[3 * v + k] = a[3 * v + k] + velocity;
      }
    }
    return tau;
  }

  PairKind kind_;
  std::mt19937_64 rng_;
  std::uniform_real_distribution<double> dist_{-1.0, 1.0};
};

constexpr int kFamilies = 7;
const char* const kFamilyNames[kFamilies] = {"general",  "coplanar",   "parallel",        "close start",
                                             "crossing", "degenerate", "grazing crossing"};

struct Tally {
  long trajectories = 0, sampled_contacts = 0, false_negatives = 0, starts_touching = 0;
  long early = 0, no_contact_stops = 0, near_miss_stops = 0, truncated = 0;
  long early_by_family[kFamilies] = {}, no_contact_by_family[kFamilies] = {};
  long iterations = 0;
  double seconds = 0.0;
};

Tally run_random_suite(PairKind kind, std::uint64_t seed, int n, const char* name) {
  TrajectoryGenerator gen(kind, seed);
  Tally tally;
  const int n_samples = 1000;
  const double s = defaults::conservative_rescaling;
  for (int i = 0; i < n; ++i) {
    const int family = i % kFamilies;
    const Trajectory tr = gen.next(family);
    const auto start = std::chrono::steady_clock::now();
    const auto r = run_ccd(kind, tr.a, tr.b, tr.xi, tr.t_max);
    tally.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    ++tally.trajectories;
    tally.iterations += r.iterations;
    tally.truncated += r.truncated;
    EXPECT_GE(r.toi, 0.0);
    EXPECT_LE(r.toi, tr.t_max);

    double magnitude = 0.0;
    for (int k = 0; k < 12; ++k) magnitude = std::fmax(magnitude, std::fmax(std::fabs(tr.a[k]), std::fabs(tr.b[k])));
    const double d0 = pair_distance(kind, tr.a);
    // Starts within rounding of contact (e.g. coplanar edges that already cross) are only
    // checked for false negatives.
    const bool starts_touching = !(d0 - tr.xi > 1e-9 * magnitude);
    tally.starts_touching += starts_touching;

    const double sampled = first_sampled_contact(kind, tr.a, tr.b, tr.xi, 0.0, tr.t_max, n_samples);
    // A built-in crossing is a contact up to the rounding of its construction.
    const double known = tr.known_contact * (1 + 1e-9);
    if (r.toi > sampled || r.toi > known) {
      ++tally.false_negatives;
      ADD_FAILURE() << name << " false negative, trajectory " << i << ": t* = " << r.toi << " > sampled contact "
                    << sampled << " or crossing " << known;
    }
    const double contact = std::fmin(sampled, tr.known_contact);
    if (contact <= tr.t_max) ++tally.sampled_contacts;
    if (starts_touching) continue;
    if (contact <= tr.t_max) {
      if (r.toi < 0.5 * contact) ++tally.early, ++tally.early_by_family[family];
    } else if (r.toi < tr.t_max) {
      const double d_min = min_sampled_distance(kind, tr.a, tr.b, 0.0, tr.t_max, n_samples);
      if (d_min - tr.xi > 1e-3 * tr.scale) {
        ++tally.no_contact_stops, ++tally.no_contact_by_family[family];
      } else {
        ++tally.near_miss_stops;
      }
    }
    // At t* the distance is above xi, with the guaranteed gap (1 - s)(d0 - xi) when the
    // iteration stopped on it (the first step is exempt only against rounding).
    if (r.toi > 0.0) {
      const double d = distance_at(kind, tr.a, tr.b, r.toi);
      EXPECT_GT(d, tr.xi) << name << " trajectory " << i;
      if (r.toi < tr.t_max && !r.truncated) {
        EXPECT_GE(d - tr.xi, (1 - s) * (d0 - tr.xi) * (1 - 1e-6) - 1e-13 * magnitude) << name << " trajectory " << i;
      }
    }
  }
  std::printf("[%s random] trajectories %ld, contacts (sampled or built-in) %ld, false negatives %ld; "
              "starting at distance <= xi (or within rounding of it) %ld; false positives: t* < 0.5 tau %ld, stop "
              "without contact (min sampled gap > 1e-3 scale) %ld; near-miss stops (gap <= 1e-3 "
              "scale, not counted) %ld; truncated %ld; mean iterations %.1f; %.0f ns per call\n",
              name, tally.trajectories, tally.sampled_contacts, tally.false_negatives, tally.starts_touching,
              tally.early, tally.no_contact_stops, tally.near_miss_stops, tally.truncated,
              double(tally.iterations) / tally.trajectories, 1e9 * tally.seconds / tally.trajectories);
  std::printf("[%s random] false positives by family (t* < 0.5 tau / stop without contact):", name);
  for (int f = 0; f < kFamilies; ++f)
    std::printf(" %s %ld/%ld;", kFamilyNames[f], tally.early_by_family[f], tally.no_contact_by_family[f]);
  std::printf("\n");
  return tally;
}

TEST(CcdRandomized, PointTriangleHasNoFalseNegatives) {
  const Tally t = run_random_suite(PairKind::point_triangle, 11, 100000, "point-triangle");
  EXPECT_EQ(t.false_negatives, 0);
  EXPECT_GT(t.sampled_contacts, t.trajectories / 10);  // the suite does exercise contacts
}

TEST(CcdRandomized, EdgeEdgeHasNoFalseNegatives) {
  const Tally t = run_random_suite(PairKind::edge_edge, 12, 100000, "edge-edge");
  EXPECT_EQ(t.false_negatives, 0);
  EXPECT_GT(t.sampled_contacts, t.trajectories / 10);
}

}  // namespace
