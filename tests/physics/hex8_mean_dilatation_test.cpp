// Tests of the mean-dilatation hex8 (hex8_mean_dilatation.hpp): gradient and exact Hessian
// against central differences, the point tangent against its analytic eigensystem, PSD of the
// Newton Hessian, agreement with the standard element where the two must agree (lambda = 0,
// homogeneous deformations), rotation invariance, and the locking it removes.
#include "physics/hex8_mean_dilatation.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>

#include "element_checks.hpp"

namespace dipc {
namespace {

using test::characteristic_length;
using test::ElementCase;
using test::Nodes;

// Poisson ratios up to 0.4999, where the element is meant to be used (test::element_cases).
std::vector<ElementCase> element_cases(std::uint64_t seed) {
  return test::element_cases(seed, 20, {0.0, 0.3, 0.49, 0.4999});
}

TEST(Hex8MeanDilatation, GradientIsCentralDifferenceOfEnergy) {
  test::expect_gradient_is_central_difference(hex8_mean_dilatation, element_cases(41));
}

TEST(Hex8MeanDilatation, ExactHessianIsCentralDifferenceOfGradient) {
  test::expect_exact_hessian_is_central_difference(hex8_mean_dilatation, hex8_mean_dilatation_exact_hessian,
                                                   element_cases(42));
}

TEST(Hex8MeanDilatation, PointTangentMatchesItsEigensystem) {
  // sum_k ev_k q_k q_k^T rebuilt from mean_dilatation_eigensystem equals the exact tangent of
  // psi_dev + p J, for pressures of both signs.
  std::mt19937_64 rng(43);
  for (int k = 0; k < 30; ++k) {
    const test::Mat3 F = test::random_deformation_gradient(rng, 0.4 + 0.1 * k, 0.3);
    const double mu = 2.0, p = (k % 3 - 1) * 5.0;
    double C[81];
    mean_dilatation_point_tangent(F.data(), mu, p, C);
    IsotropicEigensystem es;
    mean_dilatation_eigensystem(F.data(), mu, p, &es);
    double rebuilt[81] = {};
    double D[3][9];
    detail::scaling_basis(es, D);
    detail::add_scaling_block(D, es.scaling_hessian, rebuilt);
    for (int m = 0; m < 6; ++m) {
      double q[9];
      detail::pair_mode(es, m, q);
      detail::add_rank_one(es.pair_eigenvalues[m], q, rebuilt);
    }
    detail::mirror_upper(rebuilt);
    EXPECT_LT(test::max_abs_difference(C, rebuilt, 81), 1e-10 * test::max_abs(C, 81));
  }
}

TEST(Hex8MeanDilatation, ProjectedHessianIsSymmetricPsdAndOtherOutputsAgree) {
  test::expect_projected_hessian_psd(hex8_mean_dilatation, hex8_mean_dilatation_exact_hessian, element_cases(44));
}

TEST(Hex8MeanDilatation, SplitHessianPlusRankOneTermIsTheWholeHessian) {
  for (const ElementCase& c : element_cases(49)) {
    for (bool project : {false, true}) {
      double H[576], H_split[576], b[24], f2 = -1;
      if (project) {
        ASSERT_TRUE(detail::hex8_mean_dilatation<true>(c.X.data(), c.x.data(), c.lambda, c.mu, nullptr, nullptr, H));
        ASSERT_TRUE(detail::hex8_mean_dilatation<true>(c.X.data(), c.x.data(), c.lambda, c.mu, nullptr, nullptr,
                                                       H_split, b, &f2));
        EXPECT_GE(f2, 0.0);
      } else {
        ASSERT_TRUE(detail::hex8_mean_dilatation<false>(c.X.data(), c.x.data(), c.lambda, c.mu, nullptr, nullptr, H));
        ASSERT_TRUE(detail::hex8_mean_dilatation<false>(c.X.data(), c.x.data(), c.lambda, c.mu, nullptr, nullptr,
                                                        H_split, b, &f2));
      }
      for (int r = 0; r < 24; ++r)
        for (int t = 0; t < 24; ++t) H_split[24 * r + t] += f2 * b[r] * b[t];
      EXPECT_LT(test::max_abs_difference(H, H_split, 576), 1e-12 * test::max_abs(H, 576));
    }
  }
}

TEST(Hex8MeanDilatation, AgreesWithStandardElementWithoutLambdaAndForHomogeneousDeformation) {
  std::mt19937_64 rng(45);
  for (int k = 0; k < 10; ++k) {
    // A parallelepiped reference (affine map of the unit cube) and an affine deformation:
    // F is the same at every Gauss point, so ln Jbar = ln J everywhere.
    const test::Mat3 A0 = test::random_deformation_gradient(rng, 1.0, 0.2);
    const test::Mat3 A = test::random_deformation_gradient(rng, 0.5 + 0.2 * k, 0.3);
    Nodes X, x;
    for (int a = 0; a < 8; ++a) {
      const double r[3] = {hex8::corner_xi(a), hex8::corner_eta(a), hex8::corner_zeta(a)};
      for (int i = 0; i < 3; ++i) X[3 * a + i] = A0[3 * i] * r[0] + A0[3 * i + 1] * r[1] + A0[3 * i + 2] * r[2];
    }
    for (int a = 0; a < 8; ++a)
      for (int i = 0; i < 3; ++i)
        x[3 * a + i] = A[3 * i] * X[3 * a] + A[3 * i + 1] * X[3 * a + 1] + A[3 * i + 2] * X[3 * a + 2];
    double lambda, mu, e_sd, g_sd[24], e_md, g_md[24];
    lame_parameters(1e6, 0.45, &lambda, &mu);
    ASSERT_TRUE(hex8_neo_hookean(X.data(), x.data(), lambda, mu, &e_sd, g_sd, nullptr));
    ASSERT_TRUE(hex8_mean_dilatation(X.data(), x.data(), lambda, mu, &e_md, g_md, nullptr));
    EXPECT_NEAR(e_md, e_sd, 1e-12 * std::abs(e_sd));
    EXPECT_LT(test::max_abs_difference(g_md, g_sd, 24), 1e-10 * test::max_abs(g_sd, 24));
    // Without lambda the two elements are the same function of any deformation.
    const Nodes y = test::deformed_hex(rng, X, 0.8, 0.2, 0.05);
    double H_sd[576], H_md[576];
    ASSERT_TRUE(hex8_neo_hookean_exact_hessian(X.data(), y.data(), 0.0, mu, &e_sd, g_sd, H_sd));
    ASSERT_TRUE(hex8_mean_dilatation_exact_hessian(X.data(), y.data(), 0.0, mu, &e_md, g_md, H_md));
    EXPECT_NEAR(e_md, e_sd, 1e-12 * std::abs(e_sd));
    EXPECT_LT(test::max_abs_difference(H_md, H_sd, 576), 1e-10 * test::max_abs(H_sd, 576));
  }
}

TEST(Hex8MeanDilatation, EnergyIsInvariantUnderRotationAndZeroForRigidMotion) {
  for (const ElementCase& c : element_cases(46)) {
    std::mt19937_64 rng(47);
    const test::Mat3 R = test::random_rotation(rng);
    Nodes RX, Rx;
    for (int a = 0; a < 8; ++a)
      for (int i = 0; i < 3; ++i) {
        Rx[3 * a + i] = R[3 * i] * c.x[3 * a] + R[3 * i + 1] * c.x[3 * a + 1] + R[3 * i + 2] * c.x[3 * a + 2];
        RX[3 * a + i] = R[3 * i] * c.X[3 * a] + R[3 * i + 1] * c.X[3 * a + 1] + R[3 * i + 2] * c.X[3 * a + 2];
      }
    double e, e_rot, e_rigid, g_rigid[24];
    ASSERT_TRUE(hex8_mean_dilatation(c.X.data(), c.x.data(), c.lambda, c.mu, &e, nullptr, nullptr));
    ASSERT_TRUE(hex8_mean_dilatation(c.X.data(), Rx.data(), c.lambda, c.mu, &e_rot, nullptr, nullptr));
    EXPECT_NEAR(e_rot, e, 1e-11 * std::abs(e));
    ASSERT_TRUE(hex8_mean_dilatation(c.X.data(), RX.data(), c.lambda, c.mu, &e_rigid, g_rigid, nullptr));
    const double volume = std::pow(characteristic_length(c.X), 3);
    EXPECT_LT(std::abs(e_rigid), 1e-10 * (c.mu + c.lambda) * volume);
    EXPECT_LT(test::max_abs(g_rigid, 24), 1e-10 * (c.mu + c.lambda) * volume / characteristic_length(c.X));
  }
}

TEST(Hex8MeanDilatation, InvertedStateIsRejected) {
  std::mt19937_64 rng(48);
  const Nodes X = test::distorted_hex(rng, 1.0, 0.05);
  double lambda, mu, e, g[24], H[576];
  lame_parameters(1e6, 0.49, &lambda, &mu);
  Nodes mirrored = X;
  for (int a = 0; a < 8; ++a) mirrored[3 * a + 2] = -X[3 * a + 2];
  EXPECT_FALSE(hex8_mean_dilatation(X.data(), mirrored.data(), lambda, mu, &e, g, H));
  EXPECT_FALSE(hex8_elastic(VolumetricTerm::mean_dilatation, MaterialModel::neo_hookean, X.data(), mirrored.data(),
                            lambda, mu, &e, g, H));
}

TEST(Hex8MeanDilatation, IsochoricBendingModeIsNotLocked) {
  // The bending mode u_x = s x y of the cube [-1, 1]^3 (the hex8's in-plane bending, the mode
  // that locks) has det F = 1 + s y: ln J != 0 at every Gauss point, so the standard element's
  // energy grows like lambda, but the element's volume is unchanged (the mean of y is 0), so the
  // mean-dilatation energy does not depend on lambda.
  Nodes X;
  for (int a = 0; a < 8; ++a) {
    X[3 * a] = hex8::corner_xi(a);
    X[3 * a + 1] = hex8::corner_eta(a);
    X[3 * a + 2] = hex8::corner_zeta(a);
  }
  Nodes x = X;
  for (int a = 0; a < 8; ++a) x[3 * a] += 0.05 * X[3 * a] * X[3 * a + 1];
  double mu, lambda_low, lambda_high, e_sd_low, e_sd_high, e_md_low, e_md_high;
  lame_parameters(1e6, 0.3, &lambda_low, &mu);
  lambda_high = 1e4 * lambda_low;
  ASSERT_TRUE(hex8_neo_hookean(X.data(), x.data(), lambda_low, mu, &e_sd_low, nullptr, nullptr));
  ASSERT_TRUE(hex8_neo_hookean(X.data(), x.data(), lambda_high, mu, &e_sd_high, nullptr, nullptr));
  ASSERT_TRUE(hex8_mean_dilatation(X.data(), x.data(), lambda_low, mu, &e_md_low, nullptr, nullptr));
  ASSERT_TRUE(hex8_mean_dilatation(X.data(), x.data(), lambda_high, mu, &e_md_high, nullptr, nullptr));
  EXPECT_GT(e_sd_high, 10 * e_sd_low);                          // locks
  EXPECT_NEAR(e_md_high, e_md_low, 1e-9 * std::abs(e_md_low));  // does not
}

}  // namespace
}  // namespace dipc
