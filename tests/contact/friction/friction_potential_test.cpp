// Tests of the lagged friction potential per pair type (point-triangle, edge-edge,
// point-plane): finite differences energy -> gradient and gradient -> exact Hessian over
// eps_u = eps_v h from 1e-6 to 1e-1 on both sides of the stick/slip threshold, the zero
// displacement state, continuity at ||u|| = eps_u, the PSD projection, the direction and
// magnitude of the friction force, momentum conservation, mu = 0, and the normal force.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "contact/friction/friction_potential.hpp"
#include "friction_test_support.hpp"
#include "math/symmetric_eigen.hpp"

namespace dipc::contact {
namespace {

using test::Vec3;

const double kEpsValues[] = {1e-6, 1e-5, 1e-4, 1e-3, 1e-2, 1e-1};
const double kRatios[] = {0.3, 0.9, 1.5, 4.0};  // ||u|| / eps_u, both sides of the threshold
constexpr double kMu = 0.4, kLambda = 2.5;

// A rigid motion with a random rotation (Gram-Schmidt of a random frame) and translation, so
// the hand-made configurations have generic coordinates.
struct RigidMotion {
  Vec3 c0, c1, c2, t;
  Vec3 operator()(const Vec3& x) const { return x[0] * c0 + x[1] * c1 + x[2] * c2 + t; }
};

RigidMotion random_rigid_motion(std::mt19937_64& rng) {
  const Vec3 a = test::normalized(test::random_vec3(rng));
  const Vec3 b = test::normalized(test::cross(a, test::random_vec3(rng)));
  return {a, b, test::cross(a, b), test::random_vec3(rng)};
}

struct PairCase {
  std::string name;
  bool point_triangle;
  std::array<double, 12> x_lag;
};

std::vector<PairCase> pair_cases() {
  std::mt19937_64 rng(41);
  const Vec3 t0{0, 0, 0}, t1{1, 0.1, 0}, t2{0.2, 1, 0};
  const Vec3 a0{-0.5, 0, 0}, a1{0.7, 0.1, 0};
  std::vector<PairCase> cases;
  const auto pt = [&](const std::string& name, const Vec3& p) {
    const RigidMotion m = random_rigid_motion(rng);
    cases.push_back({name, true, test::stack(m(p), m(t0), m(t1), m(t2))});
  };
  const auto ee = [&](const std::string& name, const Vec3& b0, const Vec3& b1) {
    const RigidMotion m = random_rigid_motion(rng);
    cases.push_back({name, false, test::stack(m(a0), m(a1), m(b0), m(b1))});
  };
  pt("point-triangle face", {0.3, 0.3, 0.01});
  pt("point-triangle edge", {0.5, -0.2, 0.03});
  pt("point-triangle vertex", {1.3, -0.1, 0.02});
  pt("point-triangle over an edge", {0.5, 0.05, 1e-4});
  ee("edge-edge crossing", {0.1, -0.4, 0.02}, {0.0, 0.6, 0.03});
  ee("edge-edge endpoint", {0.2, 0.05, 0.01}, {0.3, 0.1, 0.9});
  ee("edge-edge nearly parallel", {-0.2, 0.02, 0.01}, {0.9, 0.02 + 1.1 * 0.1 / 1.2 + 1e-7, 0.01});
  return cases;
}

LaggedPairFriction lagged(const PairCase& c, double mu, double eps_u) {
  return c.point_triangle ? point_triangle_lagged_friction(c.x_lag.data(), mu, kLambda, eps_u)
                          : edge_edge_lagged_friction(c.x_lag.data(), mu, kLambda, eps_u);
}

// x_n near x_lag, and x = x_n + delta scaled so that ||u(x)|| = ratio * eps_u; delta also has
// components along the normal and in Gamma's null space, which friction must ignore.
void make_state(const PairCase& c, const LaggedPairFriction& f, double ratio, std::mt19937_64& rng,
                std::array<double, 12>& x, std::array<double, 12>& xn) {
  std::uniform_real_distribution<double> u(-1, 1);
  std::array<double, 12> delta;
  for (int i = 0; i < 12; ++i) {
    xn[i] = c.x_lag[i] + 1e-3 * u(rng);
    delta[i] = u(rng);
  }
  double u0[2];
  tangential_displacement(delta.data(), std::array<double, 12>{}.data(), f, u0);
  const double s = ratio * f.eps_u / std::hypot(u0[0], u0[1]);
  for (int i = 0; i < 12; ++i) x[i] = xn[i] + s * delta[i];
}

TEST(PairFriction, GradientAndHessianMatchFiniteDifferences) {
  std::mt19937_64 rng(43);
  for (const PairCase& c : pair_cases())
    for (double eps : kEpsValues)
      for (double ratio : kRatios) {
        const LaggedPairFriction f = lagged(c, kMu, eps);
        std::array<double, 12> x, xn;
        make_state(c, f, ratio, rng, x, xn);
        double u[2];
        tangential_displacement(x.data(), xn.data(), f, u);
        ASSERT_NEAR(std::hypot(u[0], u[1]), ratio * eps, 1e-9 * eps);
        const double h = 1e-4 * eps * std::fmin(ratio, 1.0);
        const auto energy = [&](const double* y) { return friction_energy(y, xn.data(), f); };
        const auto gradient = [&](const double* y, double* g) { friction_gradient(y, xn.data(), f, g); };
        double g[12], H[144];
        friction_gradient(x.data(), xn.data(), f, g);
        friction_hessian_unprojected(x.data(), xn.data(), f, H);
        const auto g_fd = test::central_difference_gradient(energy, x.data(), 12, h);
        const auto H_fd = test::central_difference_jacobian(gradient, x.data(), 12, 12, h);
        EXPECT_LE(test::max_abs_diff(g, g_fd.data(), 12), 1e-6 * test::max_abs(g, 12))
            << c.name << " eps " << eps << " |u|/eps " << ratio;
        EXPECT_LE(test::max_abs_diff(H, H_fd.data(), 144), 1e-6 * test::max_abs(H, 144))
            << c.name << " eps " << eps << " |u|/eps " << ratio;
        // Only the tangential part matters: the value is mu lambda f0(|u|).
        EXPECT_NEAR(friction_energy(x.data(), xn.data(), f), kMu * kLambda * friction_f0(ratio * eps, eps),
                    1e-9 * kMu * kLambda * eps);
      }
}

TEST(PairFriction, ZeroDisplacementIsTheMinimumWithAStickingSpringHessian) {
  for (const PairCase& c : pair_cases())
    for (double eps : kEpsValues) {
      const LaggedPairFriction f = lagged(c, kMu, eps);
      const std::array<double, 12>& xn = c.x_lag;
      double g[12], H[144];
      friction_gradient(xn.data(), xn.data(), f, g);
      for (double gi : g) EXPECT_EQ(gi, 0.0) << c.name;
      EXPECT_DOUBLE_EQ(friction_energy(xn.data(), xn.data(), f), kMu * kLambda * eps / 3.0);
      // At u = 0 the Hessian is mu lambda (2/eps) Gamma^T P P^T Gamma; the gradient is
      // differentiable there, so finite differences apply.
      friction_hessian_unprojected(xn.data(), xn.data(), f, H);
      const auto gradient = [&](const double* y, double* out) { friction_gradient(y, xn.data(), f, out); };
      const auto H_fd = test::central_difference_jacobian(gradient, xn.data(), 12, 12, 1e-7 * eps);
      EXPECT_LE(test::max_abs_diff(H, H_fd.data(), 144), 1e-5 * test::max_abs(H, 144)) << c.name << " " << eps;
      double Hp[144];
      friction_hessian(xn.data(), xn.data(), f, Hp);
      EXPECT_LE(test::max_abs_diff(H, Hp, 144), 1e-14 * test::max_abs(H, 144));
      // Energy grows away from u = 0 in every direction.
      std::mt19937_64 rng(45);
      std::uniform_real_distribution<double> u(-1, 1);
      std::array<double, 12> x;
      for (int i = 0; i < 12; ++i) x[i] = xn[i] + 1e-2 * eps * u(rng);
      EXPECT_GT(friction_energy(x.data(), xn.data(), f), friction_energy(xn.data(), xn.data(), f));
    }
}

TEST(PairFriction, ContinuousAtTheStickSlipThreshold) {
  std::mt19937_64 rng(47);
  for (const PairCase& c : pair_cases())
    for (double eps : {1e-6, 1e-3, 1e-1}) {
      const LaggedPairFriction f = lagged(c, kMu, eps);
      std::array<double, 12> below, above, xn;
      make_state(c, f, 1.0 - 1e-9, rng, below, xn);
      for (int i = 0; i < 12; ++i) above[i] = xn[i] + (below[i] - xn[i]) * ((1.0 + 1e-9) / (1.0 - 1e-9));
      double ub[2], ua[2];
      tangential_displacement(below.data(), xn.data(), f, ub);
      tangential_displacement(above.data(), xn.data(), f, ua);
      ASSERT_LT(std::hypot(ub[0], ub[1]), eps);
      ASSERT_GT(std::hypot(ua[0], ua[1]), eps);
      const double Db = friction_energy(below.data(), xn.data(), f), Da = friction_energy(above.data(), xn.data(), f);
      EXPECT_NEAR(Db, Da, 1e-7 * Da);
      double gb[12], ga[12], Hb[144], Ha[144];
      friction_gradient(below.data(), xn.data(), f, gb);
      friction_gradient(above.data(), xn.data(), f, ga);
      EXPECT_LE(test::max_abs_diff(gb, ga, 12), 1e-7 * test::max_abs(ga, 12)) << c.name;
      friction_hessian(below.data(), xn.data(), f, Hb);
      friction_hessian(above.data(), xn.data(), f, Ha);
      EXPECT_LE(test::max_abs_diff(Hb, Ha, 144), 1e-6 * test::max_abs(Ha, 144)) << c.name;
    }
}

double min_eigenvalue(const double* H, int n) {
  double w[12], V[144];
  symmetric_eigen<12>(H, n, w, V);
  return w[0];
}

TEST(PairFriction, ProjectedHessianIsPsdAndEqualsTheExactOneUpToRounding) {
  std::mt19937_64 rng(49);
  for (const PairCase& c : pair_cases())
    for (double eps : kEpsValues)
      for (double ratio : {0.0, 0.01, 0.5, 0.999, 1.0, 1.001, 3.0, 1e3}) {
        const LaggedPairFriction f = lagged(c, kMu, eps);
        std::array<double, 12> x, xn;
        if (ratio == 0.0) {
          x = xn = c.x_lag;
        } else {
          make_state(c, f, ratio, rng, x, xn);
        }
        double H[144], He[144];
        friction_hessian(x.data(), xn.data(), f, H);
        friction_hessian_unprojected(x.data(), xn.data(), f, He);
        const double scale = test::max_abs(He, 144);
        EXPECT_GE(min_eigenvalue(H, 12), -1e-13 * scale) << c.name << " eps " << eps << " ratio " << ratio;
        EXPECT_LE(test::max_abs_diff(H, He, 144), 1e-12 * scale);
        for (int i = 0; i < 12; ++i)
          for (int j = 0; j < 12; ++j) EXPECT_EQ(H[12 * i + j], H[12 * j + i]);
      }
}

// The inner 2x2 matrix has eigenvector u/|u| with eigenvalue mu lambda f1'(|u|) and the
// orthogonal one with mu lambda f1(|u|)/|u|; projection clamps the former's rounding to >= 0.
TEST(FrictionInnerHessian, SpectrumIsF1PrimeAlongUAndF1OverYAcross) {
  std::mt19937_64 rng(51);
  std::uniform_real_distribution<double> angle(0, 6.283185307179586);
  for (double eps : kEpsValues)
    for (double ratio : {0.01, 0.5, 0.9, 1.0, 1.5, 40.0}) {
      const double y = ratio * eps, th = angle(rng);
      const double u[2] = {y * std::cos(th), y * std::sin(th)};
      const double e[2] = {std::cos(th), std::sin(th)}, q[2] = {-std::sin(th), std::cos(th)};
      for (bool project : {false, true}) {
        double M[4];
        friction_inner_hessian(u, eps, kMu * kLambda, project, M);
        const double along = kMu * kLambda * friction_f1_derivative(y, eps);
        const double across = kMu * kLambda * friction_f1_over_y(y, eps);
        for (int i = 0; i < 2; ++i) {
          EXPECT_NEAR(M[2 * i] * e[0] + M[2 * i + 1] * e[1], along * e[i], 1e-13 * across);
          EXPECT_NEAR(M[2 * i] * q[0] + M[2 * i + 1] * q[1], across * q[i], 1e-13 * across);
        }
        if (project) {
          const double lowest = 0.5 * (M[0] + M[3]) - std::hypot(0.5 * (M[0] - M[3]), M[1]);
          EXPECT_GE(lowest, -1e-14 * across) << "eps " << eps << " |u|/eps " << ratio;
        }
      }
    }
}

// The friction force -dD on the first point opposes the tangential relative motion; when
// sliding (|u| >= eps_u) its magnitude is Coulomb's mu lambda; the forces on the four points
// sum to zero.
TEST(PairFriction, ForceOpposesSlidingWithCoulombMagnitude) {
  std::mt19937_64 rng(53);
  for (const PairCase& c : pair_cases())
    for (double eps : {1e-5, 1e-2})
      for (double ratio : {0.5, 2.0, 100.0}) {
        const LaggedPairFriction f = lagged(c, kMu, eps);
        const std::array<double, 12>& xn = c.x_lag;
        // Tangential motion of the first point (p, or the whole edge a so the relative motion
        // of the closest points is the same delta).
        std::uniform_real_distribution<double> u(-1, 1);
        const double a = u(rng), b = u(rng), s = ratio * eps / std::hypot(a, b);
        Vec3 delta;
        for (int i = 0; i < 3; ++i) delta[i] = s * (a * f.basis[2 * i] + b * f.basis[2 * i + 1]);
        std::array<double, 12> x = xn;
        const int moved = c.point_triangle ? 1 : 2;
        for (int k = 0; k < moved; ++k)
          for (int i = 0; i < 3; ++i) x[3 * k + i] += delta[i];
        double g[12];
        friction_gradient(x.data(), xn.data(), f, g);
        Vec3 force{0, 0, 0}, total{0, 0, 0};
        for (int k = 0; k < moved; ++k) force = force + Vec3{-g[3 * k], -g[3 * k + 1], -g[3 * k + 2]};
        for (int k = 0; k < 4; ++k) total = total + Vec3{g[3 * k], g[3 * k + 1], g[3 * k + 2]};
        EXPECT_NEAR(dot(force, delta) / (test::norm(force) * test::norm(delta)), -1.0, 1e-10) << c.name;
        const double expected = kMu * kLambda * friction_f1(ratio * eps, eps);
        EXPECT_NEAR(test::norm(force), expected, 1e-8 * kMu * kLambda) << c.name << " ratio " << ratio;
        EXPECT_LE(test::norm(total), 1e-13 * kMu * kLambda) << c.name;
        // A general motion (with normal components): friction still does negative work.
        std::array<double, 12> y;
        for (int i = 0; i < 12; ++i) y[i] = xn[i] + ratio * eps * u(rng);
        friction_gradient(y.data(), xn.data(), f, g);
        double work = 0;
        for (int i = 0; i < 12; ++i) work -= g[i] * (y[i] - xn[i]);
        EXPECT_LE(work, 0.0) << c.name;
      }
}

TEST(PairFriction, ZeroFrictionCoefficientGivesZeros) {
  std::mt19937_64 rng(55);
  for (const PairCase& c : pair_cases()) {
    const LaggedPairFriction f = lagged(c, 0.0, 1e-3);
    std::array<double, 12> x, xn;
    make_state(c, lagged(c, kMu, 1e-3), 2.0, rng, x, xn);
    double g[12], H[144];
    EXPECT_EQ(friction_energy(x.data(), xn.data(), f), 0.0);
    friction_gradient(x.data(), xn.data(), f, g);
    friction_hessian(x.data(), xn.data(), f, H);
    EXPECT_EQ(test::max_abs(g, 12), 0.0);
    EXPECT_EQ(test::max_abs(H, 144), 0.0);
  }
}

// ---- point-plane ----

struct PlaneState {
  LaggedPointPlaneFriction f;
  std::array<double, 3> x, xn;
};

PlaneState plane_state(std::mt19937_64& rng, double mu, double eps, double ratio) {
  const Vec3 n = test::random_vec3(rng);
  PlaneState s{point_plane_lagged_friction(n.data(), mu, kLambda, eps), {}, {}};
  const Vec3 p = test::random_vec3(rng), delta = test::random_vec3(rng);
  double u0[2];
  const double zero[3] = {0, 0, 0};
  tangential_displacement(delta.data(), zero, s.f, u0);
  const double scale = ratio * eps / std::hypot(u0[0], u0[1]);
  for (int i = 0; i < 3; ++i) {
    s.xn[i] = p[i];
    s.x[i] = p[i] + scale * delta[i];
  }
  return s;
}

TEST(PointPlaneFriction, GradientAndHessianMatchFiniteDifferences) {
  std::mt19937_64 rng(61);
  for (double eps : kEpsValues)
    for (double ratio : kRatios)
      for (int k = 0; k < 5; ++k) {
        const PlaneState s = plane_state(rng, kMu, eps, ratio);
        const double h = 1e-4 * eps * std::fmin(ratio, 1.0);
        const auto energy = [&](const double* y) { return friction_energy(y, s.xn.data(), s.f); };
        const auto gradient = [&](const double* y, double* g) { friction_gradient(y, s.xn.data(), s.f, g); };
        double g[3], H[9];
        friction_gradient(s.x.data(), s.xn.data(), s.f, g);
        friction_hessian_unprojected(s.x.data(), s.xn.data(), s.f, H);
        const auto g_fd = test::central_difference_gradient(energy, s.x.data(), 3, h);
        const auto H_fd = test::central_difference_jacobian(gradient, s.x.data(), 3, 3, h);
        EXPECT_LE(test::max_abs_diff(g, g_fd.data(), 3), 1e-6 * test::max_abs(g, 3)) << eps << " " << ratio;
        EXPECT_LE(test::max_abs_diff(H, H_fd.data(), 9), 1e-6 * test::max_abs(H, 9)) << eps << " " << ratio;
        double Hp[9];
        friction_hessian(s.x.data(), s.xn.data(), s.f, Hp);
        EXPECT_GE(min_eigenvalue(Hp, 3), -1e-13 * test::max_abs(H, 9));
        EXPECT_LE(test::max_abs_diff(H, Hp, 9), 1e-12 * test::max_abs(H, 9));
      }
}

TEST(PointPlaneFriction, ZeroDisplacementContinuityDirectionAndZeroMu) {
  std::mt19937_64 rng(63);
  for (double eps : kEpsValues) {
    PlaneState s = plane_state(rng, kMu, eps, 1.0 - 1e-9);
    double g[3], ga[3], H[9];
    friction_gradient(s.xn.data(), s.xn.data(), s.f, g);
    for (double gi : g) EXPECT_EQ(gi, 0.0);
    EXPECT_DOUBLE_EQ(friction_energy(s.xn.data(), s.xn.data(), s.f), kMu * kLambda * eps / 3.0);
    friction_hessian(s.xn.data(), s.xn.data(), s.f, H);
    // mu lambda (2/eps) P P^T: the normal direction has no stiffness.
    const Vec3 c0{s.f.basis[0], s.f.basis[2], s.f.basis[4]}, c1{s.f.basis[1], s.f.basis[3], s.f.basis[5]};
    const Vec3 n = test::cross(c0, c1);
    for (int a = 0; a < 3; ++a)
      EXPECT_NEAR(H[3 * a] * n[0] + H[3 * a + 1] * n[1] + H[3 * a + 2] * n[2], 0.0, 1e-14 * kMu * kLambda / eps);
    EXPECT_NEAR(H[0] + H[4] + H[8], 2 * kMu * kLambda * 2 / eps, 1e-12 * kMu * kLambda / eps);
    // Continuity across |u| = eps_u.
    std::array<double, 3> above;
    for (int i = 0; i < 3; ++i) above[i] = s.xn[i] + (s.x[i] - s.xn[i]) * ((1 + 1e-9) / (1 - 1e-9));
    friction_gradient(s.x.data(), s.xn.data(), s.f, g);
    friction_gradient(above.data(), s.xn.data(), s.f, ga);
    EXPECT_LE(test::max_abs_diff(g, ga, 3), 1e-7 * kMu * kLambda);
    EXPECT_NEAR(friction_energy(s.x.data(), s.xn.data(), s.f), friction_energy(above.data(), s.xn.data(), s.f),
                1e-7 * kMu * kLambda * eps);
    // Sliding along the plane: force opposite to the motion, magnitude mu lambda.
    const Vec3 delta = (3 * eps) * test::normalized(0.3 * c0 + (-0.8) * c1);
    const std::array<double, 3> slid = {s.xn[0] + delta[0], s.xn[1] + delta[1], s.xn[2] + delta[2]};
    friction_gradient(slid.data(), s.xn.data(), s.f, g);
    const Vec3 force{-g[0], -g[1], -g[2]};
    EXPECT_NEAR(dot(force, delta) / (test::norm(force) * test::norm(delta)), -1.0, 1e-12);
    EXPECT_NEAR(test::norm(force), kMu * kLambda, 1e-12);
    // Zero friction coefficient.
    const PlaneState z = plane_state(rng, 0.0, eps, 2.0);
    EXPECT_EQ(friction_energy(z.x.data(), z.xn.data(), z.f), 0.0);
    friction_gradient(z.x.data(), z.xn.data(), z.f, g);
    friction_hessian(z.x.data(), z.xn.data(), z.f, H);
    EXPECT_EQ(test::max_abs(g, 3), 0.0);
    EXPECT_EQ(test::max_abs(H, 9), 0.0);
  }
}

// The isotropic majorizer (friction_hessian with FrictionModel::majorizer): PSD, and the
// quadratic it makes with the energy and gradient at x lies on or above the energy everywhere,
// also where the move crosses the stick disc to slide the other way (large random moves, and
// the move that reverses u); along the slip it is at least as stiff as the exact Hessian.
TEST(FrictionMajorizer, BoundsTheEnergyFromAboveAndTouchesItAtX) {
  std::mt19937_64 rng(71);
  std::uniform_real_distribution<double> unit(-1, 1);
  for (const PairCase& c : pair_cases())
    for (double eps : kEpsValues)
      for (double ratio : kRatios) {
        const LaggedPairFriction f = lagged(c, kMu, eps);
        std::array<double, 12> x, xn;
        make_state(c, f, ratio, rng, x, xn);
        double g[12], Hm[144], H[144];
        friction_gradient(x.data(), xn.data(), f, g);
        friction_hessian(x.data(), xn.data(), f, FrictionModel::majorizer, Hm);
        friction_hessian_unprojected(x.data(), xn.data(), f, H);
        const double scale = test::max_abs(Hm, 144);
        EXPECT_GE(min_eigenvalue(Hm, 12), -1e-13 * scale) << c.name;
        const double E0 = friction_energy(x.data(), xn.data(), f);
        const auto model_gap = [&](const std::array<double, 12>& d) {  // model(x + d) - E(x + d)
          std::array<double, 12> y;
          double gd = 0, dHd = 0;
          for (int i = 0; i < 12; ++i) {
            y[i] = x[i] + d[i];
            gd += g[i] * d[i];
            for (int j = 0; j < 12; ++j) dHd += d[i] * Hm[12 * i + j] * d[j];
          }
          return E0 + gd + 0.5 * dHd - friction_energy(y.data(), xn.data(), f);
        };
        const double roundoff = 1e-12 * kMu * kLambda * eps * (1 + 100 * ratio);
        for (int k = 0; k < 20; ++k) {
          std::array<double, 12> d;
          const double size = ratio * eps * std::pow(10.0, unit(rng) * 2);  // 0.01 to 100 slips
          for (double& di : d) di = size * unit(rng);
          EXPECT_GE(model_gap(d), -roundoff) << c.name << " eps " << eps << " |u|/eps " << ratio;
        }
        // x_n - (x - x_n): the move that turns u into -u.
        std::array<double, 12> reverse;
        for (int i = 0; i < 12; ++i) reverse[i] = -2 * (x[i] - xn[i]);
        EXPECT_GE(model_gap(reverse), -roundoff) << c.name;
        // Along the slip (the move x - x_n that made it) the majorizer is at least as stiff.
        std::array<double, 12> along;
        double along2 = 0;
        for (int i = 0; i < 12; ++i) along[i] = x[i] - xn[i], along2 += along[i] * along[i];
        const auto curvature = [&](const double* M, const std::array<double, 12>& d) {
          double v = 0;
          for (int i = 0; i < 12; ++i)
            for (int j = 0; j < 12; ++j) v += d[i] * M[12 * i + j] * d[j];
          return v;
        };
        EXPECT_GE(curvature(Hm, along), curvature(H, along) - 1e-12 * scale * along2) << c.name;
      }
}

TEST(FrictionMajorizer, PointPlaneBoundsTheEnergyAndEqualsMuLambdaF1OverYInTheTangentPlane) {
  std::mt19937_64 rng(73);
  std::uniform_real_distribution<double> unit(-1, 1);
  for (double eps : kEpsValues)
    for (double ratio : kRatios)
      for (int k = 0; k < 5; ++k) {
        const PlaneState s = plane_state(rng, kMu, eps, ratio);
        double g[3], Hm[9];
        friction_gradient(s.x.data(), s.xn.data(), s.f, g);
        friction_hessian(s.x.data(), s.xn.data(), s.f, FrictionModel::majorizer, Hm);
        // mu lambda f1(y)/y P P^T: trace twice the factor, no stiffness along the normal.
        const double factor = kMu * kLambda * friction_f1_over_y(ratio * eps, eps);
        EXPECT_NEAR(Hm[0] + Hm[4] + Hm[8], 2 * factor, 1e-9 * factor);
        const double E0 = friction_energy(s.x.data(), s.xn.data(), s.f);
        for (int t = 0; t < 20; ++t) {
          std::array<double, 3> d, y;
          const double size = ratio * eps * std::pow(10.0, unit(rng) * 2);
          double gd = 0, dHd = 0;
          for (int i = 0; i < 3; ++i) d[i] = size * unit(rng), y[i] = s.x[i] + d[i];
          for (int i = 0; i < 3; ++i) {
            gd += g[i] * d[i];
            for (int j = 0; j < 3; ++j) dHd += d[i] * Hm[3 * i + j] * d[j];
          }
          EXPECT_GE(E0 + gd + 0.5 * dHd - friction_energy(y.data(), s.xn.data(), s.f),
                    -1e-12 * kMu * kLambda * eps * (1 + 100 * ratio))
              << eps << " " << ratio;
        }
      }
}

TEST(FrictionMajorizer, SlipReversesOnlyBetweenOpposedSlidingStates) {
  const double eps = 1e-3;
  const double sliding[2] = {2e-3, 1e-3}, opposed[2] = {-3e-3, -0.5e-3}, turned[2] = {1e-3, 3e-3},
               stuck[2] = {-0.5e-3, 0}, across[2] = {-1e-3, 2e-3};
  EXPECT_TRUE(slip_reverses(sliding, opposed, eps));
  EXPECT_TRUE(slip_reverses(opposed, sliding, eps));
  EXPECT_FALSE(slip_reverses(sliding, turned, eps));   // less than 90 degrees apart
  EXPECT_FALSE(slip_reverses(sliding, stuck, eps));    // lands in the stick disc
  EXPECT_FALSE(slip_reverses(stuck, opposed, eps));    // starts in it
  EXPECT_FALSE(slip_reverses(sliding, sliding, eps));  // no move
  EXPECT_FALSE(slip_reverses(sliding, across, eps));   // exactly 90 degrees is not a reversal
}

// lambda = -kappa b'(d) 2 sqrt(d) is minus the derivative of kappa b(s^2) with respect to the
// unsquared distance s, checked on IPC's barrier b(d) = -(d - dhat)^2 ln(d/dhat).
TEST(FrictionNormalForce, IsTheBarrierForceAlongTheUnsquaredDistance) {
  const double kappa = 3e4;
  for (double dhat : {1e-10, 1e-6, 1e-2}) {
    const auto b = [&](double d) { return -(d - dhat) * (d - dhat) * std::log(d / dhat); };
    const auto db = [&](double d) { return -2 * (d - dhat) * std::log(d / dhat) - (d - dhat) * (d - dhat) / d; };
    for (double frac : {1e-4, 0.1, 0.5, 0.9}) {
      const double d = frac * dhat, s = std::sqrt(d), h = 1e-6 * s;
      const double dbds = (kappa * b((s + h) * (s + h)) - kappa * b((s - h) * (s - h))) / (2 * h);
      const double lambda = friction_normal_force(kappa, db(d), d);
      EXPECT_GT(lambda, 0.0);
      EXPECT_NEAR(lambda, -dbds, 1e-6 * lambda) << "dhat " << dhat << " d/dhat " << frac;
    }
    EXPECT_EQ(friction_normal_force(kappa, db(dhat), dhat), 0.0);  // no force at the activation distance
  }
}

}  // namespace
}  // namespace dipc::contact
