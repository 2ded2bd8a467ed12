// Tests of the hex8 neo-Hookean element: gradient and exact Hessian against central
// differences on distorted elements, PSD and symmetry of the projected Hessian, rigid-motion
// invariance, rejection of inverted states, and the volume ratio.
#include "physics/hex8_elasticity.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>

#include "element_checks.hpp"

namespace dipc {
namespace {

using test::ElementCase;
using test::Nodes;

// Standard hex8 cases: Poisson ratios 0, 0.3, 0.49 (test::element_cases).
std::vector<ElementCase> element_cases(std::uint64_t seed) { return test::element_cases(seed, 15, {0.0, 0.3, 0.49}); }

TEST(Hex8Elasticity, GradientIsCentralDifferenceOfEnergy) {
  test::expect_gradient_is_central_difference(hex8_neo_hookean, element_cases(21));
}

TEST(Hex8Elasticity, ExactHessianIsCentralDifferenceOfGradient) {
  test::expect_exact_hessian_is_central_difference(hex8_neo_hookean, hex8_neo_hookean_exact_hessian, element_cases(22));
}

TEST(Hex8Elasticity, ProjectedHessianIsSymmetricPsdAndOtherOutputsAgree) {
  test::expect_projected_hessian_psd(hex8_neo_hookean, hex8_neo_hookean_exact_hessian, element_cases(23));
}

TEST(Hex8Elasticity, UniformSmallExpansionHessianNeedsNoProjection) {
  // x = 1.005 X: every quadrature tangent is positive definite (see neo_hookean_test), so
  // the projected and exact element Hessians coincide.
  std::mt19937_64 rng(24);
  const Nodes X = test::distorted_hex(rng, 1.0, 0.12);
  Nodes x;
  for (int k = 0; k < 24; ++k) x[k] = 1.005 * X[k];
  double lambda, mu, H[576], H_exact[576];
  lame_parameters(1e6, 0.45, &lambda, &mu);
  ASSERT_TRUE(hex8_neo_hookean(X.data(), x.data(), lambda, mu, nullptr, nullptr, H));
  ASSERT_TRUE(hex8_neo_hookean_exact_hessian(X.data(), x.data(), lambda, mu, nullptr, nullptr, H_exact));
  EXPECT_LT(test::max_abs_difference(H, H_exact, 576), 1e-10 * test::max_abs(H_exact, 576));
}

TEST(Hex8Elasticity, RigidMotionHasZeroEnergyAndGradient) {
  std::mt19937_64 rng(25);
  for (int k = 0; k < 10; ++k) {
    const Nodes X = test::distorted_hex(rng, 2.0, 0.12);
    const test::Mat3 R = test::random_rotation(rng);
    const double t[3] = {0.5 * k, -3.0, 1.25};
    Nodes x;
    for (int a = 0; a < 8; ++a)
      for (int i = 0; i < 3; ++i)
        x[3 * a + i] = R[3 * i] * X[3 * a] + R[3 * i + 1] * X[3 * a + 1] + R[3 * i + 2] * X[3 * a + 2] + t[i];
    double lambda, mu, e, g[24];
    lame_parameters(1e6, 0.3, &lambda, &mu);
    ASSERT_TRUE(hex8_neo_hookean(X.data(), x.data(), lambda, mu, &e, g, nullptr));
    // Scale of a unit strain: energy ~ mu * volume (8), gradient entries ~ mu * area (4).
    EXPECT_LT(std::abs(e), 1e-12 * mu * 8);
    EXPECT_LT(test::max_abs(g, 24), 1e-12 * mu * 4);
    EXPECT_NEAR(hex8_min_volume_ratio(X.data(), x.data()), 1.0, 1e-12);
  }
}

TEST(Hex8Elasticity, EnergyIsInvariantAndGradientCovariantUnderRotation) {
  for (const ElementCase& c : element_cases(26)) {
    std::mt19937_64 rng(27);
    const test::Mat3 R = test::random_rotation(rng);
    Nodes Rx;
    for (int a = 0; a < 8; ++a)
      for (int i = 0; i < 3; ++i)
        Rx[3 * a + i] = R[3 * i] * c.x[3 * a] + R[3 * i + 1] * c.x[3 * a + 1] + R[3 * i + 2] * c.x[3 * a + 2];
    double e, g[24], e_rot, g_rot[24];
    ASSERT_TRUE(hex8_neo_hookean(c.X.data(), c.x.data(), c.lambda, c.mu, &e, g, nullptr));
    ASSERT_TRUE(hex8_neo_hookean(c.X.data(), Rx.data(), c.lambda, c.mu, &e_rot, g_rot, nullptr));
    EXPECT_NEAR(e_rot, e, 1e-12 * std::abs(e));
    double Rg[24];
    for (int a = 0; a < 8; ++a)
      for (int i = 0; i < 3; ++i)
        Rg[3 * a + i] = R[3 * i] * g[3 * a] + R[3 * i + 1] * g[3 * a + 1] + R[3 * i + 2] * g[3 * a + 2];
    EXPECT_LT(test::max_abs_difference(g_rot, Rg, 24), 1e-11 * test::max_abs(g, 24));
  }
}

TEST(Hex8Elasticity, VolumeRatioOfAffineMapIsItsDeterminant) {
  std::mt19937_64 rng(28);
  const Nodes X = test::distorted_hex(rng, 1.0, 0.12);
  const test::Mat3 A = test::random_deformation_gradient(rng, 0.37, 0.3);
  Nodes x;
  for (int a = 0; a < 8; ++a)
    for (int i = 0; i < 3; ++i)
      x[3 * a + i] = A[3 * i] * X[3 * a] + A[3 * i + 1] * X[3 * a + 1] + A[3 * i + 2] * X[3 * a + 2];
  EXPECT_NEAR(hex8_min_volume_ratio(X.data(), x.data()), 0.37, 1e-12);
}

TEST(Hex8Elasticity, InvertedStateIsRejected) {
  std::mt19937_64 rng(29);
  const Nodes X = test::distorted_hex(rng, 1.0, 0.05);
  double lambda, mu, e, g[24], H[576];
  lame_parameters(1e6, 0.3, &lambda, &mu);
  // Mirror the element: det F = -1 everywhere.
  Nodes mirrored = X;
  for (int a = 0; a < 8; ++a) mirrored[3 * a + 2] = -X[3 * a + 2];
  EXPECT_FALSE(hex8_neo_hookean(X.data(), mirrored.data(), lambda, mu, &e, g, H));
  EXPECT_FALSE(hex8_neo_hookean_exact_hessian(X.data(), mirrored.data(), lambda, mu, &e, nullptr, nullptr));
  EXPECT_NEAR(hex8_min_volume_ratio(X.data(), mirrored.data()), -1.0, 1e-2);
  // Flatten to zero volume: det F = 0 must be rejected too.
  Nodes flat = X;
  for (int a = 0; a < 8; ++a) flat[3 * a + 2] = 0.0;
  EXPECT_FALSE(hex8_neo_hookean(X.data(), flat.data(), lambda, mu, &e, nullptr, nullptr));
}

TEST(Hex8Elasticity, CornerInversionMissedByGaussPointsIsCaught) {
  // Unit cube with corner 6 pushed towards the centre: the Jacobian at that corner turns
  // negative while all eight Gauss points stay positive, so the energy is defined but the
  // state must still be rejected through the volume ratio.
  Nodes X;
  for (int a = 0; a < 8; ++a) {
    X[3 * a] = 0.5 * (1 + hex8::corner_xi(a));
    X[3 * a + 1] = 0.5 * (1 + hex8::corner_eta(a));
    X[3 * a + 2] = 0.5 * (1 + hex8::corner_zeta(a));
  }
  Nodes x = X;
  x[18] = x[19] = x[20] = 0.6;  // corner Jacobian I - 0.4*ones: det -0.2
  double lambda, mu, e;
  lame_parameters(1e6, 0.3, &lambda, &mu);
  EXPECT_TRUE(hex8_neo_hookean(X.data(), x.data(), lambda, mu, &e, nullptr, nullptr));
  EXPECT_LT(hex8_min_volume_ratio(X.data(), x.data()), 0.0);
}

}  // namespace
}  // namespace dipc
