// Tests of the friction mollifier (f0, f1 and the derived factors of the gradient and
// Hessian) and of the closed-form 2x2 PSD projection.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "contact/friction/friction_mollifier.hpp"
#include "contact/friction/symmetric_2x2_psd.hpp"
#include "math/symmetric_eigen.hpp"

namespace dipc::contact {
namespace {

const double kEpsValues[] = {1e-6, 1e-5, 1e-4, 1e-3, 1e-2, 1e-1};
// y / eps_u on both sides of the stick/slip threshold, away from it (f1' has a kink there).
const double kRatios[] = {0.01, 0.3, 0.7, 0.95, 1.05, 2.0, 10.0};

TEST(FrictionMollifier, ClosedFormValues) {
  for (double eps : kEpsValues) {
    EXPECT_DOUBLE_EQ(friction_f0(0.0, eps), eps / 3.0);
    EXPECT_EQ(friction_f1(0.0, eps), 0.0);
    EXPECT_DOUBLE_EQ(friction_f1_over_y(0.0, eps), 2.0 / eps);
    EXPECT_DOUBLE_EQ(friction_f1_derivative(0.0, eps), 2.0 / eps);
    const double y = 0.5 * eps;  // f1 = -1/4 + 1 = 3/4, f0 = eps(1/4 - 1/24 + 1/3)
    EXPECT_DOUBLE_EQ(friction_f1(y, eps), 0.75);
    EXPECT_DOUBLE_EQ(friction_f0(y, eps), eps * (0.25 - 1.0 / 24.0 + 1.0 / 3.0));
    EXPECT_DOUBLE_EQ(friction_f0(3 * eps, eps), 3 * eps);  // sliding: D = mu lambda ||u||
    EXPECT_EQ(friction_f1(3 * eps, eps), 1.0);
    EXPECT_EQ(friction_f1_derivative(3 * eps, eps), 0.0);
  }
}

TEST(FrictionMollifier, DerivativesMatchFiniteDifferences) {
  for (double eps : kEpsValues)
    for (double r : kRatios) {
      const double y = r * eps, h = 1e-5 * y;
      const double yp = y + h, ym = y - h, dy = yp - ym;
      const double df0 = (friction_f0(yp, eps) - friction_f0(ym, eps)) / dy;
      const double df1 = (friction_f1(yp, eps) - friction_f1(ym, eps)) / dy;
      EXPECT_NEAR(df0, friction_f1(y, eps), 1e-8) << "eps " << eps << " y/eps " << r;
      EXPECT_NEAR(df1 * eps, friction_f1_derivative(y, eps) * eps, 1e-8) << "eps " << eps << " y/eps " << r;
      // (f1/y)' = (f1' y - f1)/y^2, so the Hessian term is (f1/y)' / y.
      const double dratio = (friction_f1_over_y(yp, eps) - friction_f1_over_y(ym, eps)) / dy;
      const double term = friction_f1_derivative_term(y, eps);
      EXPECT_NEAR(dratio / y, term, 1e-7 * std::fabs(term)) << "eps " << eps << " y/eps " << r;
      EXPECT_NEAR(friction_f1_over_y(y, eps), friction_f1(y, eps) / y, 1e-12 * friction_f1_over_y(y, eps));
      EXPECT_NEAR(term, (friction_f1_derivative(y, eps) * y - friction_f1(y, eps)) / (y * y * y),
                  1e-9 * std::fabs(term));
    }
}

TEST(FrictionMollifier, ContinuousAtThreshold) {
  for (double eps : kEpsValues) {
    const double below = std::nextafter(eps, 0.0);
    EXPECT_NEAR(friction_f0(below, eps), friction_f0(eps, eps), 1e-15 * eps);
    EXPECT_NEAR(friction_f1(below, eps), friction_f1(eps, eps), 1e-14);
    EXPECT_NEAR(friction_f1_derivative(below, eps) * eps, friction_f1_derivative(eps, eps) * eps, 1e-14);
    EXPECT_NEAR(friction_f1_over_y(below, eps) * eps, friction_f1_over_y(eps, eps) * eps, 1e-14);
    EXPECT_NEAR(friction_f1_derivative_term(below, eps) * eps * eps * eps,
                friction_f1_derivative_term(eps, eps) * eps * eps * eps, 1e-14);
  }
}

TEST(FrictionMollifier, MonotoneBetweenZeroAndOne) {
  // f1 ramps from 0 to 1 (friction force never exceeds Coulomb's mu lambda); f0 increases.
  const double eps = 1e-3;
  double previous_f0 = friction_f0(0.0, eps), previous_f1 = 0.0;
  for (int k = 1; k <= 300; ++k) {
    const double y = k * eps / 100.0;
    const double f0 = friction_f0(y, eps), f1 = friction_f1(y, eps);
    EXPECT_GT(f0, previous_f0);
    EXPECT_GE(f1, previous_f1);
    EXPECT_LE(f1, 1.0);
    previous_f0 = f0;
    previous_f1 = f1;
  }
}

void expect_projection_matches_reference(const double M_in[4]) {
  double M[4] = {M_in[0], M_in[1], M_in[1], M_in[3]};
  project_symmetric_2x2_to_psd(M);
  double R[4] = {M_in[0], M_in[1], M_in[1], M_in[3]};
  project_psd<2>(R, 2);  // Jacobi eigen-decomposition, independent of the closed form
  const double scale = std::fabs(M_in[0]) + std::fabs(M_in[1]) + std::fabs(M_in[3]);
  for (int k = 0; k < 4; ++k) EXPECT_NEAR(M[k], R[k], 1e-13 * scale) << "entry " << k;
  EXPECT_EQ(M[1], M[2]);
  // PSD: non-negative diagonal and determinant.
  EXPECT_GE(M[0], -1e-14 * scale);
  EXPECT_GE(M[3], -1e-14 * scale);
  EXPECT_GE(M[0] * M[3] - M[1] * M[2], -1e-13 * scale * scale);
}

TEST(Symmetric2x2Psd, MatchesEigenClampingOnRandomMatrices) {
  std::mt19937_64 rng(11);
  std::normal_distribution<double> n(0.0, 1.0);
  int indefinite = 0;
  for (int k = 0; k < 2000; ++k) {
    const double M[4] = {n(rng), n(rng), 0.0, n(rng)};
    indefinite += M[0] * M[3] - M[1] * M[1] < 0;
    expect_projection_matches_reference(M);
  }
  EXPECT_GT(indefinite, 100);  // the random set exercises the clamping branch
}

TEST(Symmetric2x2Psd, SpecialCases) {
  const double psd[4] = {2.0, 0.5, 0.5, 1.0};
  double M[4] = {2.0, 0.5, 0.5, 1.0};
  project_symmetric_2x2_to_psd(M);
  for (int k = 0; k < 4; ++k) EXPECT_EQ(M[k], psd[k]);  // PSD input is untouched
  double N[4] = {-1.0, 0.2, 0.2, -3.0};
  project_symmetric_2x2_to_psd(N);
  for (int k = 0; k < 4; ++k) EXPECT_EQ(N[k], 0.0);  // negative definite -> 0
  double D[4] = {-2.0, 0.0, 0.0, 5.0};
  project_symmetric_2x2_to_psd(D);
  EXPECT_NEAR(D[0], 0.0, 1e-15);
  EXPECT_NEAR(D[1], 0.0, 1e-15);
  EXPECT_NEAR(D[3], 5.0, 1e-15);
  const double rank_one_indefinite[4] = {1.0, 3.0, 3.0, 1.0};  // eigenvalues 4 and -2
  expect_projection_matches_reference(rank_one_indefinite);
}

}  // namespace
}  // namespace dipc::contact
