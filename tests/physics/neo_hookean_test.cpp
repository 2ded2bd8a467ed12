// Tests of the neo-Hookean point functions: P and dP/dF against central differences, the
// SVD, the analytic eigensystem against the exact tangent, and the analytic PSD projection
// against the numeric (Jacobi) projection.
#include "physics/neo_hookean.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "math/symmetric_eigen.hpp"
#include "physics/materials.hpp"
#include "physics_test_support.hpp"

namespace dipc {
namespace {

struct Material {
  double E, nu;
};
const Material kMaterials[] = {{1.0, 0.0}, {1e5, 0.3}, {1e7, 0.49}, {2e11, 0.45}};

// Random F with det F from 1e-2 (strong compression) to 5 (strong stretch), and
// anisotropy so singular values differ by up to a few times.
struct Sample {
  test::Mat3 F;
  double min_sigma;
};
std::vector<Sample> sample_deformations(std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<Sample> out;
  for (double J : {1e-2, 0.1, 0.5, 0.9, 1.0, 1.3, 2.0, 5.0})
    for (double anisotropy : {0.0, 0.1, 0.4}) {
      Sample s;
      s.F = test::random_deformation_gradient(rng, J, anisotropy, &s.min_sigma);
      out.push_back(s);
    }
  return out;
}

TEST(NeoHookean, LameParameters) {
  double lambda, mu;
  lame_parameters(1e6, 0.25, &lambda, &mu);
  EXPECT_DOUBLE_EQ(lambda, 4e5);
  EXPECT_DOUBLE_EQ(mu, 4e5);
  lame_parameters(3.0, 0.0, &lambda, &mu);
  EXPECT_DOUBLE_EQ(lambda, 0.0);
  EXPECT_DOUBLE_EQ(mu, 1.5);
}

TEST(NeoHookean, RestStateHasZeroEnergyAndStress) {
  const double I[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  double P[9];
  EXPECT_EQ(neo_hookean_energy(I, 3.0, 2.0), 0.0);
  neo_hookean_stress(I, 3.0, 2.0, P);
  EXPECT_LT(test::max_abs(P, 9), 1e-15);
}

TEST(NeoHookean, EnergyOfUniformStretchMatchesClosedForm) {
  // F = s I: psi = 3 mu/2 (s^2 - 1) - 3 mu ln s + 9 lambda/2 (ln s)^2.
  const double s = 1.7, lambda = 2.5, mu = 0.8;
  const double F[9] = {s, 0, 0, 0, s, 0, 0, 0, s};
  const double expected = 1.5 * mu * (s * s - 1) - 3 * mu * std::log(s) + 4.5 * lambda * std::log(s) * std::log(s);
  EXPECT_NEAR(neo_hookean_energy(F, lambda, mu), expected, 1e-14 * std::abs(expected));
}

TEST(NeoHookean, StressIsCentralDifferenceOfEnergy) {
  for (const Material& m : kMaterials) {
    double lambda, mu;
    lame_parameters(m.E, m.nu, &lambda, &mu);
    for (const Sample& s : sample_deformations(11)) {
      const double h = 1e-6 * s.min_sigma;
      double P[9], P_fd[9];
      neo_hookean_stress(s.F.data(), lambda, mu, P);
      const auto energy = [&](const double* F, double* e) { *e = neo_hookean_energy(F, lambda, mu); };
      test::central_difference(energy, s.F.data(), 9, 1, h, P_fd);
      // mu is the stress scale where P itself vanishes (F a rotation).
      EXPECT_LT(test::max_abs_difference(P, P_fd, 9), 1e-6 * (test::max_abs(P, 9) + mu))
          << "E=" << m.E << " nu=" << m.nu << " J=" << det3x3(s.F.data());
    }
  }
}

TEST(NeoHookean, StressDerivativeIsCentralDifferenceOfStress) {
  for (const Material& m : kMaterials) {
    double lambda, mu;
    lame_parameters(m.E, m.nu, &lambda, &mu);
    for (const Sample& s : sample_deformations(12)) {
      const double h = 1e-6 * s.min_sigma;
      double C[81];
      neo_hookean_stress_derivative(s.F.data(), lambda, mu, C);
      double C_fd[81];
      const auto stress = [&](const double* F, double* P) { neo_hookean_stress(F, lambda, mu, P); };
      test::central_difference(stress, s.F.data(), 9, 9, h, C_fd);
      EXPECT_LT(test::max_abs_difference(C, C_fd, 81), 1e-6 * test::max_abs(C, 81))
          << "E=" << m.E << " nu=" << m.nu << " J=" << det3x3(s.F.data());
      EXPECT_EQ(test::max_asymmetry(C, 9), 0.0);
    }
  }
}

TEST(NeoHookean, RotationVariantSvdReconstructsF) {
  std::mt19937_64 rng(13);
  std::vector<test::Mat3> cases;
  for (const Sample& s : sample_deformations(14)) cases.push_back(s.F);
  cases.push_back(test::random_rotation(rng));  // three equal singular values
  test::Mat3 stretched = test::random_rotation(rng);
  for (int i = 0; i < 3; ++i) stretched[3 * i] *= 2.0;  // two equal singular values
  cases.push_back(stretched);
  for (const test::Mat3& F : cases) {
    double U[9], sigma[3], V[9];
    rotation_variant_svd(F.data(), U, sigma, V);
    EXPECT_NEAR(det3x3(U), 1.0, 1e-13);
    EXPECT_NEAR(det3x3(V), 1.0, 1e-13);
    EXPECT_GE(sigma[0], sigma[1]);
    EXPECT_GE(sigma[1] * (1 + 1e-12), sigma[2]);
    EXPECT_GT(sigma[2], 0.0);
    double R[9];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        R[3 * i + j] = 0;
        for (int k = 0; k < 3; ++k) R[3 * i + j] += U[3 * i + k] * sigma[k] * V[3 * j + k];
      }
    EXPECT_LT(test::max_abs_difference(R, F.data(), 9), 1e-14 * 10 * sigma[0]);
  }
}

TEST(NeoHookean, UnclampedEigensystemRebuildsExactTangent) {
  for (const Material& m : kMaterials) {
    double lambda, mu;
    lame_parameters(m.E, m.nu, &lambda, &mu);
    std::vector<Sample> samples = sample_deformations(15);
    Sample identity{{1, 0, 0, 0, 1, 0, 0, 0, 1}, 1.0};
    samples.push_back(identity);
    for (const Sample& s : samples) {
      double exact[81], rebuilt[81];
      neo_hookean_stress_derivative(s.F.data(), lambda, mu, exact);
      neo_hookean_stress_derivative_eigensystem(s.F.data(), lambda, mu, false, rebuilt);
      EXPECT_LT(test::max_abs_difference(exact, rebuilt, 81), 1e-10 * test::max_abs(exact, 81))
          << "E=" << m.E << " nu=" << m.nu << " J=" << det3x3(s.F.data());
    }
  }
}

TEST(NeoHookean, AnalyticProjectionMatchesJacobiProjection) {
  int indefinite_cases = 0;
  for (const Material& m : kMaterials) {
    double lambda, mu;
    lame_parameters(m.E, m.nu, &lambda, &mu);
    for (const Sample& s : sample_deformations(16)) {
      double exact[81], analytic[81];
      neo_hookean_stress_derivative(s.F.data(), lambda, mu, exact);
      stress_derivative_psd<NeoHookean>(s.F.data(), lambda, mu, analytic);
      double w[9], V[81];
      symmetric_eigen(exact, 9, w, V);
      if (w[0] < -1e-8 * std::max(std::abs(w[0]), std::abs(w[8]))) ++indefinite_cases;
      double numeric[81];
      for (int k = 0; k < 81; ++k) numeric[k] = exact[k];
      project_psd(numeric, 9);
      const double scale = test::max_abs(exact, 81);
      EXPECT_LT(test::max_abs_difference(analytic, numeric, 81), 1e-8 * scale)
          << "E=" << m.E << " nu=" << m.nu << " J=" << det3x3(s.F.data());
      EXPECT_EQ(test::max_asymmetry(analytic, 9), 0.0);
      symmetric_eigen(analytic, 9, w, V);
      EXPECT_GE(w[0], -1e-10 * std::abs(w[8]));
    }
  }
  // The comparison above is only meaningful if some tangents really needed projecting.
  EXPECT_GT(indefinite_cases, 10);
}

TEST(NeoHookean, AnalyticProjectionKeepsPositiveDefiniteTangent) {
  // Uniform expansion F = s R with 1 < s < ~1.01: every eigenvalue of dP/dF is positive
  // (twists mu (1 - 1/s^2) + 3 lambda ln s / s^2; flips and the smallest scaling mode
  // mu (1 + 1/s^2) - 3 lambda ln s / s^2, positive while 3 lambda ln s < mu (1 + s^2) even
  // for nu = 0.49), so the projection must change nothing.
  std::mt19937_64 rng(17);
  for (const Material& m : kMaterials) {
    double lambda, mu;
    lame_parameters(m.E, m.nu, &lambda, &mu);
    for (double s : {1.002, 1.005, 1.01}) {
      test::Mat3 F = test::random_rotation(rng);
      for (double& v : F) v *= s;
      double exact[81], analytic[81], w[9], V[81];
      neo_hookean_stress_derivative(F.data(), lambda, mu, exact);
      symmetric_eigen(exact, 9, w, V);
      ASSERT_GT(w[0], 0.0) << "test premise: tangent is positive definite";
      stress_derivative_psd<NeoHookean>(F.data(), lambda, mu, analytic);
      EXPECT_LT(test::max_abs_difference(exact, analytic, 81), 1e-10 * test::max_abs(exact, 81));
    }
  }
}

}  // namespace
}  // namespace dipc
