// Point-plane CCD (analytic half-space obstacles, src/contact/ccd/time_of_impact.hpp):
// closed-form impact time on hand-made cases (either side, tilted and non-unit normals,
// min_separation, parallel and receding motion, t_max, a cut step, scaling), and 10^5
// random trajectories against a long-double solution and dense sampling.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <limits>
#include <random>

#include "ccd_test_support.hpp"

namespace {

using dipc::contact::point_plane_time_of_impact;
using dipc::test::Vec3;

double toi(const Vec3& p0, const Vec3& p1, const Vec3& o, const Vec3& n, double xi, double t_max = 1.0) {
  return point_plane_time_of_impact(p0.data(), p1.data(), o.data(), n.data(), xi, t_max);
}

// Exact time within a few ulps, never after it.
void expect_just_before(double t, double tau) {
  EXPECT_LE(t, tau);
  EXPECT_GE(t, tau * (1 - 1e-14));
}

const Vec3 kO{0, 0, 0}, kZ{0, 0, 1};

TEST(PointPlaneCcd, HeadOn) {
  expect_just_before(toi({0.3, 0.2, 1}, {0.3, 0.2, -1}, kO, kZ, 0.0), 0.5);
  // Oblique motion: only the normal component matters.
  expect_just_before(toi({0.3, 0.2, 1}, {5.3, -4.2, -3}, kO, kZ, 0.0), 0.25);
}

TEST(PointPlaneCcd, TiltedAndNonUnitNormals) {
  expect_just_before(toi({0.3, 0.2, 1}, {0.3, 0.2, -1}, kO, {0, 0, 5}, 0.0), 0.5);
  // Plane x + y + z = 1: signed distances 2/sqrt(3) and -4/sqrt(3) -> tau = 1/3.
  expect_just_before(toi({1, 1, 1}, {-1, -1, -1}, {1, 0, 0}, {1, 1, 1}, 0.0), 1.0 / 3.0);
}

TEST(PointPlaneCcd, EitherSide) {
  expect_just_before(toi({0, 0, -1}, {0, 0, 1}, kO, kZ, 0.0), 0.5);
  expect_just_before(toi({0, 0, -1}, {0, 0, 1}, kO, kZ, 0.2), 0.4);
}

TEST(PointPlaneCcd, MinSeparation) { expect_just_before(toi({0.3, 0.2, 1}, {0.3, 0.2, -1}, kO, kZ, 0.1), 0.45); }

TEST(PointPlaneCcd, NoApproachReturnsTMaxExactly) {
  EXPECT_EQ(toi({0, 0, 1}, {0, 0, 1}, kO, kZ, 0.0), 1.0);        // zero motion
  EXPECT_EQ(toi({0, 0, 1}, {7, -3, 1}, kO, kZ, 0.0), 1.0);       // parallel to the plane
  EXPECT_EQ(toi({0, 0, 1}, {0, 0, 3}, kO, kZ, 0.0, 0.7), 0.7);   // receding
  EXPECT_EQ(toi({0, 0, 1}, {0, 0, -1}, kO, kZ, 0.0, 0.3), 0.3);  // impact after t_max
}

TEST(PointPlaneCcd, DegenerateInputsReturnZero) {
  EXPECT_EQ(toi({0, 0, 0}, {0, 0, 1}, kO, kZ, 0.0), 0.0);          // on the plane
  EXPECT_EQ(toi({0, 0, 0.05}, {0, 0, 1}, kO, kZ, 0.1), 0.0);       // within xi
  EXPECT_EQ(toi({0, 0, 1}, {0, 0, -1}, kO, {0, 0, 0}, 0.0), 0.0);  // no normal
}

TEST(PointPlaneCcd, CutStepDoesNotCollapse) {
  Vec3 p0{0.3, 0.2, 1};
  const Vec3 p1{0.3, 0.2, -1};
  double reached = 0.0;
  for (int round = 0; round < 20; ++round) {
    const double remaining = (0.5 - reached) / (1.0 - reached);
    const double t = toi(p0, p1, kO, kZ, 0.0);
    ASSERT_GT(t, 0.0) << "round " << round;
    EXPECT_NEAR(t, remaining, 1e-12) << "round " << round;
    for (int k = 0; k < 3; ++k) p0[k] += 0.8 * t * (p1[k] - p0[k]);
    reached += 0.8 * t * (1.0 - reached);
  }
  EXPECT_GT(p0[2], 0.0);
}

TEST(PointPlaneCcd, UniformScalingGivesSameTime) {
  const Vec3 p0{1, 1, 1}, p1{-1, -2, -1}, o{1, 0, 0}, n{1, 1, 1};
  const double reference = toi(p0, p1, o, n, 0.1);
  for (int k = -4; k <= 4; ++k) {
    const double f = std::pow(10.0, k);
    auto sc = [f](const Vec3& v) { return Vec3{v[0] * f, v[1] * f, v[2] * f}; };
    EXPECT_NEAR(toi(sc(p0), sc(p1), sc(o), n, 0.1 * f), reference, 1e-14) << "scale 1e" << k;
  }
}

// Long-double signed distance, independent of the function under test.
long double signed_distance(const Vec3& p, const Vec3& o, const Vec3& n) {
  long double dot = 0, nn = 0;
  for (int k = 0; k < 3; ++k) {
    dot += (long double)n[k] * ((long double)p[k] - (long double)o[k]);
    nn += (long double)n[k] * n[k];
  }
  return dot / std::sqrt(nn);
}

TEST(PointPlaneCcd, RandomTrajectoriesAgainstExactAndSampling) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const int n_traj = 100000, n_samples = 1000;
  long contacts = 0, false_negatives = 0, false_positives = 0;
  for (int i = 0; i < n_traj; ++i) {
    const double scale = std::pow(10.0, 4 * u(rng));
    const Vec3 p0{u(rng) * scale, u(rng) * scale, u(rng) * scale};
    const Vec3 p1{u(rng) * scale, u(rng) * scale, u(rng) * scale};
    const Vec3 o{0.5 * u(rng) * scale, 0.5 * u(rng) * scale, 0.5 * u(rng) * scale};
    const Vec3 n{u(rng), u(rng), u(rng)};
    const double xi = (i % 3) * 0.02 * scale;
    const double t_max = i % 4 == 0 ? 0.6 : 1.0;
    const double t = toi(p0, p1, o, n, xi, t_max);
    ASSERT_GE(t, 0.0);
    ASSERT_LE(t, t_max);

    // Exact: |s(tau)| = xi on the starting side (s linear in time).
    long double s0 = signed_distance(p0, o, n), s1 = signed_distance(p1, o, n);
    if (s0 < 0) s0 = -s0, s1 = -s1;
    long double tau = std::numeric_limits<long double>::infinity();
    if (s0 <= xi)
      tau = 0;
    else if (s1 < s0)
      tau = (s0 - xi) / (s0 - s1);

    // Dense sampling: the first sampled time with |s| <= xi.
    double sampled = std::numeric_limits<double>::infinity();
    for (int k = 0; k <= n_samples; ++k) {
      const double tk = t_max * k / n_samples;
      Vec3 p;
      for (int c = 0; c < 3; ++c) p[c] = p0[c] + tk * (p1[c] - p0[c]);
      if (std::fabs(signed_distance(p, o, n)) <= xi) {
        sampled = tk;
        break;
      }
    }
    if (sampled <= t_max) {
      ++contacts;
      if (t > sampled) ++false_negatives;
    }
    if (tau <= t_max) {
      if (t > tau) ++false_negatives;
      if (t < 0.5 * tau) ++false_positives;
      // Well-conditioned cases (start clearly outside xi) are exact to rounding.
      if (s0 - xi > 1e-6 * scale) {
        EXPECT_NEAR(t, (double)tau, 1e-9) << "trajectory " << i;
      }
    } else if (t < t_max) {
      ++false_positives;
    }
  }
  std::cout << "[point-plane random] trajectories " << n_traj << ", sampled contacts " << contacts
            << ", false negatives " << false_negatives << ", false positives " << false_positives << "\n";
  EXPECT_GT(contacts, n_traj / 10);
  EXPECT_EQ(false_negatives, 0);
  EXPECT_EQ(false_positives, 0);
}

}  // namespace
