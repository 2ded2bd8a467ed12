// Tests of the stable neo-Hookean material (stable_neo_hookean.hpp) and of its hex8 element:
// P and dP/dF against central differences (also for inverted F), the analytic eigensystem
// against the exact tangent, the analytic PSD projection against the Jacobi projection, the
// rest state, rotation invariance, agreement with neo-Hookean in the small-strain limit, and
// the element's gradient and exact Hessian against central differences.
#include "physics/stable_neo_hookean.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>
#include <vector>

#include "element_checks.hpp"
#include "math/symmetric_eigen.hpp"
#include "physics/hex8_elasticity.hpp"
#include "physics/hex8_mean_dilatation.hpp"
#include "physics/materials.hpp"
#include "physics/neo_hookean.hpp"
#include "physics_test_support.hpp"

namespace dipc {
namespace {

struct Young {
  double E, nu;
};
const Young kMaterials[] = {{1.0, 0.0}, {1e5, 0.3}, {1e7, 0.49}, {2e11, 0.45}, {1e6, -0.5}};

// Random anisotropic F with det F from 1e-2 to 5 and, with_inverted, the same mirrored
// (det F < 0) and one flat F (det F = 0).
struct Sample {
  test::Mat3 F;
  double scale;  // a step scale for finite differences: the largest singular value
};
std::vector<Sample> sample_deformations(std::uint64_t seed, bool with_inverted) {
  std::mt19937_64 rng(seed);
  std::vector<Sample> out;
  for (double J : {1e-2, 0.1, 0.5, 0.9, 1.0, 1.3, 2.0, 5.0})
    for (double anisotropy : {0.0, 0.1, 0.4}) {
      Sample s;
      s.F = test::random_deformation_gradient(rng, J, anisotropy);
      s.scale = 1.0;
      for (double v : s.F) s.scale = std::max(s.scale, std::abs(v));
      out.push_back(s);
      if (with_inverted) {
        // The same F mirrored through a random plane with normal n: (I - 2 n n^T) F, det = -J.
        const test::Mat3 R = test::random_rotation(rng);
        test::Mat3 reflection = {1, 0, 0, 0, 1, 0, 0, 0, 1};
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j) reflection[3 * i + j] -= 2 * R[3 * i] * R[3 * j];
        out.push_back({test::multiply(reflection, s.F), s.scale});
      }
    }
  if (with_inverted) {
    // A flat F (det F = 0, rank 2).
    const test::Mat3 flat = {1.2, 0.1, 0, -0.2, 0.9, 0, 0.3, 0.1, 0};
    out.push_back({test::multiply(test::random_rotation(rng), flat), 1.2});
  }
  return out;
}

TEST(StableNeoHookean, ReparametrisationOfSection34) {
  double ls, ms;
  stable_neo_hookean_parameters(3.0, 1.5, &ls, &ms);
  EXPECT_DOUBLE_EQ(ms, 2.0);
  EXPECT_DOUBLE_EQ(ls, 3.0 + 1.25);
}

TEST(StableNeoHookean, RestStateHasZeroEnergyAndStress) {
  const double I[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  for (const Young& m : kMaterials) {
    double lambda, mu, P[9];
    lame_parameters(m.E, m.nu, &lambda, &mu);
    EXPECT_LE(std::abs(stable_neo_hookean_energy(I, lambda, mu)), 1e-15 * mu);
    stable_neo_hookean_stress(I, lambda, mu, P);
    EXPECT_LT(test::max_abs(P, 9), 1e-15 * mu) << "E=" << m.E << " nu=" << m.nu;
  }
}

TEST(StableNeoHookean, EnergyOfUniformStretchMatchesThePapersForm) {
  // F = s I in the paper's own form, eq. 14 with alpha = 1 + 3 mu'/(4 lambda'), minus its
  // value at F = I.
  const double s = 1.3, lambda = 2.5, mu = 0.8;
  const double ms = 4.0 / 3.0 * mu, ls = lambda + 5.0 / 6.0 * mu, alpha = 1 + 0.75 * ms / ls;
  auto paper = [&](double Ic, double J) {
    return 0.5 * ms * (Ic - 3) + 0.5 * ls * (J - alpha) * (J - alpha) - 0.5 * ms * std::log(Ic + 1);
  };
  const double expected = paper(3 * s * s, s * s * s) - paper(3, 1);
  const double F[9] = {s, 0, 0, 0, s, 0, 0, 0, s};
  EXPECT_NEAR(stable_neo_hookean_energy(F, lambda, mu), expected, 1e-14 * std::abs(expected));
}

TEST(StableNeoHookean, StressIsCentralDifferenceOfEnergyAlsoWhenInverted) {
  for (const Young& m : kMaterials) {
    double lambda, mu;
    lame_parameters(m.E, m.nu, &lambda, &mu);
    for (const Sample& s : sample_deformations(31, true)) {
      const double h = 1e-6 * s.scale;
      double P[9], P_fd[9];
      stable_neo_hookean_stress(s.F.data(), lambda, mu, P);
      ASSERT_TRUE(std::isfinite(stable_neo_hookean_energy(s.F.data(), lambda, mu)));
      for (int k = 0; k < 9; ++k) {
        test::Mat3 Fp = s.F, Fm = s.F;
        Fp[k] += h;
        Fm[k] -= h;
        const double ep = stable_neo_hookean_energy(Fp.data(), lambda, mu);
        P_fd[k] = (ep - stable_neo_hookean_energy(Fm.data(), lambda, mu)) / (2 * h);
      }
      EXPECT_LT(test::max_abs_difference(P, P_fd, 9), 1e-6 * (test::max_abs(P, 9) + mu))
          << "E=" << m.E << " nu=" << m.nu << " J=" << det3x3(s.F.data());
    }
  }
}

TEST(StableNeoHookean, StressDerivativeIsCentralDifferenceOfStressAlsoWhenInverted) {
  for (const Young& m : kMaterials) {
    double lambda, mu;
    lame_parameters(m.E, m.nu, &lambda, &mu);
    for (const Sample& s : sample_deformations(32, true)) {
      const double h = 1e-6 * s.scale;
      double C[81], C_fd[81];
      stable_neo_hookean_stress_derivative(s.F.data(), lambda, mu, C);
      for (int l = 0; l < 9; ++l) {
        test::Mat3 Fp = s.F, Fm = s.F;
        Fp[l] += h;
        Fm[l] -= h;
        double Pp[9], Pm[9];
        stable_neo_hookean_stress(Fp.data(), lambda, mu, Pp);
        stable_neo_hookean_stress(Fm.data(), lambda, mu, Pm);
        for (int k = 0; k < 9; ++k) C_fd[9 * k + l] = (Pp[k] - Pm[k]) / (2 * h);
      }
      EXPECT_LT(test::max_abs_difference(C, C_fd, 81), 1e-6 * test::max_abs(C, 81))
          << "E=" << m.E << " nu=" << m.nu << " J=" << det3x3(s.F.data());
      EXPECT_EQ(test::max_asymmetry(C, 9), 0.0);
    }
  }
}

// sum_k lambda_k q_k q_k^T over the nine modes of the analytic eigensystem, unclamped.
void rebuild_from_eigensystem(const IsotropicEigensystem& es, double C[81]) {
  double D[3][9];
  detail::scaling_basis(es, D);
  for (int k = 0; k < 81; ++k) C[k] = 0;
  detail::add_scaling_block(D, es.scaling_hessian, C);
  for (int m = 0; m < 6; ++m) {
    double q[9];
    detail::pair_mode(es, m, q);
    detail::add_rank_one(es.pair_eigenvalues[m], q, C);
  }
  detail::mirror_upper(C);
}

TEST(StableNeoHookean, EigensystemRebuildsExactTangentAlsoWhenInverted) {
  for (const Young& m : kMaterials) {
    double lambda, mu;
    lame_parameters(m.E, m.nu, &lambda, &mu);
    std::vector<Sample> samples = sample_deformations(33, true);
    samples.push_back({{1, 0, 0, 0, 1, 0, 0, 0, 1}, 1.0});
    for (const Sample& s : samples) {
      double exact[81], rebuilt[81];
      stable_neo_hookean_stress_derivative(s.F.data(), lambda, mu, exact);
      IsotropicEigensystem es;
      stable_neo_hookean_eigensystem(s.F.data(), lambda, mu, &es);
      rebuild_from_eigensystem(es, rebuilt);
      EXPECT_LT(test::max_abs_difference(exact, rebuilt, 81), 1e-10 * test::max_abs(exact, 81))
          << "E=" << m.E << " nu=" << m.nu << " J=" << det3x3(s.F.data());
    }
  }
}

TEST(StableNeoHookean, AnalyticProjectionMatchesJacobiProjection) {
  int indefinite_cases = 0;
  for (const Young& m : kMaterials) {
    double lambda, mu;
    lame_parameters(m.E, m.nu, &lambda, &mu);
    for (const Sample& s : sample_deformations(34, true)) {
      double exact[81], analytic[81], numeric[81], w[9], V[81];
      stable_neo_hookean_stress_derivative(s.F.data(), lambda, mu, exact);
      stress_derivative_psd<StableNeoHookean>(s.F.data(), lambda, mu, analytic);
      symmetric_eigen(exact, 9, w, V);
      if (w[0] < -1e-8 * std::max(std::abs(w[0]), std::abs(w[8]))) ++indefinite_cases;
      for (int k = 0; k < 81; ++k) numeric[k] = exact[k];
      project_psd(numeric, 9);
      EXPECT_LT(test::max_abs_difference(analytic, numeric, 81), 1e-8 * test::max_abs(exact, 81))
          << "E=" << m.E << " nu=" << m.nu << " J=" << det3x3(s.F.data());
      EXPECT_EQ(test::max_asymmetry(analytic, 9), 0.0);
      symmetric_eigen(analytic, 9, w, V);
      EXPECT_GE(w[0], -1e-10 * std::abs(w[8]));
    }
  }
  EXPECT_GT(indefinite_cases, 10) << "the projection was not exercised";
}

TEST(StableNeoHookean, RotationInvariance) {
  std::mt19937_64 rng(35);
  for (const Young& m : kMaterials) {
    double lambda, mu;
    lame_parameters(m.E, m.nu, &lambda, &mu);
    for (const Sample& s : sample_deformations(36, true)) {
      const test::Mat3 R = test::random_rotation(rng);
      const test::Mat3 RF = test::multiply(R, s.F);
      const double e = stable_neo_hookean_energy(s.F.data(), lambda, mu);
      const double e_rot = stable_neo_hookean_energy(RF.data(), lambda, mu);
      EXPECT_NEAR(e_rot, e, 1e-12 * (std::abs(e) + mu * s.scale * s.scale));
      // P(R F) = R P(F).
      double P[9], P_rot[9];
      stable_neo_hookean_stress(s.F.data(), lambda, mu, P);
      stable_neo_hookean_stress(RF.data(), lambda, mu, P_rot);
      test::Mat3 Pm;
      std::copy(P, P + 9, Pm.begin());
      const test::Mat3 RP = test::multiply(R, Pm);
      EXPECT_LT(test::max_abs_difference(RP.data(), P_rot, 9), 1e-12 * (test::max_abs(P, 9) + mu * s.scale));
    }
  }
}

TEST(StableNeoHookean, SmallStrainLimitIsNeoHookeansLinearElasticity) {
  // Same tangent at F = I (that of linear elasticity with lambda, mu), so for F = I + eps A
  // the energies agree to O(eps^3) and the stresses to O(eps^2).
  std::mt19937_64 rng(37);
  std::normal_distribution<double> n(0.0, 1.0);
  const double I[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  for (const Young& m : kMaterials) {
    double lambda, mu;
    lame_parameters(m.E, m.nu, &lambda, &mu);
    double C_snh[81], C_nh[81];
    stable_neo_hookean_stress_derivative(I, lambda, mu, C_snh);
    neo_hookean_stress_derivative(I, lambda, mu, C_nh);
    EXPECT_LT(test::max_abs_difference(C_snh, C_nh, 81), 1e-14 * test::max_abs(C_nh, 81)) << m.nu;
    double A[9];
    for (double& a : A) a = n(rng);
    double previous_ratio = 0;
    for (double eps : {1e-2, 1e-3, 1e-4}) {
      double F[9];
      for (int k = 0; k < 9; ++k) F[k] = I[k] + eps * A[k];
      const double e_nh = neo_hookean_energy(F, lambda, mu), e_snh = stable_neo_hookean_energy(F, lambda, mu);
      const double scale = (lambda > 0 ? lambda : 0) + mu;
      // |difference| / eps^3 stays bounded: the quadratic terms are the same.
      const double ratio = std::abs(e_snh - e_nh) / (scale * eps * eps * eps);
      EXPECT_LT(ratio, 50.0) << "nu=" << m.nu << " eps=" << eps;
      if (previous_ratio > 0) {
        EXPECT_LT(ratio, 1.5 * previous_ratio + 1e-6);
      }
      previous_ratio = ratio;
      // Energy itself is O(eps^2): the agreement is not trivial.
      EXPECT_GT(e_nh, 1e-3 * mu * eps * eps);
      double P_nh[9], P_snh[9];
      neo_hookean_stress(F, lambda, mu, P_nh);
      stable_neo_hookean_stress(F, lambda, mu, P_snh);
      EXPECT_LT(test::max_abs_difference(P_nh, P_snh, 9), 50.0 * scale * eps * eps);
    }
  }
}

// ---- the hex8 element ---------------------------------------------------------------------

using test::characteristic_length;
using test::ElementCase;
using test::Nodes;

std::vector<ElementCase> element_cases(std::uint64_t seed) { return test::element_cases(seed, 15, {0.0, 0.3, 0.49}); }

const auto kElement = hex8_element<StableNeoHookean>;
const auto kElementExact = hex8_element_exact_hessian<StableNeoHookean>;

TEST(Hex8StableNeoHookean, GradientIsCentralDifferenceOfEnergy) {
  test::expect_gradient_is_central_difference(kElement, element_cases(41));
}

TEST(Hex8StableNeoHookean, ExactHessianIsCentralDifferenceOfGradient) {
  test::expect_exact_hessian_is_central_difference(kElement, kElementExact, element_cases(42));
}

TEST(Hex8StableNeoHookean, ProjectedHessianIsSymmetricPsd) {
  test::expect_projected_hessian_psd(kElement, kElementExact, element_cases(43));
}

TEST(Hex8StableNeoHookean, RigidMotionLeavesEnergyAndRestIsStressFree) {
  std::mt19937_64 rng(44);
  for (const ElementCase& c : element_cases(45)) {
    const test::Mat3 R = test::random_rotation(rng);
    Nodes RX, Rx;
    for (int a = 0; a < 8; ++a)
      for (int i = 0; i < 3; ++i) {
        RX[3 * a + i] = 2.0 + R[3 * i] * c.X[3 * a] + R[3 * i + 1] * c.X[3 * a + 1] + R[3 * i + 2] * c.X[3 * a + 2];
        Rx[3 * a + i] = R[3 * i] * c.x[3 * a] + R[3 * i + 1] * c.x[3 * a + 1] + R[3 * i + 2] * c.x[3 * a + 2];
      }
    double e, e_rot, e_rigid, g_rigid[24], H[576];
    ASSERT_TRUE(kElement(c.X.data(), c.x.data(), c.lambda, c.mu, &e, nullptr, H));
    ASSERT_TRUE(kElement(c.X.data(), Rx.data(), c.lambda, c.mu, &e_rot, nullptr, nullptr));
    EXPECT_NEAR(e_rot, e, 1e-11 * e);
    // A rigidly moved reference configuration: zero energy and zero force.
    ASSERT_TRUE(kElement(c.X.data(), RX.data(), c.lambda, c.mu, &e_rigid, g_rigid, nullptr));
    const double L = characteristic_length(c.X);
    EXPECT_LT(std::abs(e_rigid), 1e-12 * c.mu * L * L * L);
    EXPECT_LT(test::max_abs(g_rigid, 24), 1e-10 * test::max_abs(H, 576) * L);
  }
}

TEST(Hex8StableNeoHookean, InvertedElementIsRefusedLikeEveryMaterial) {
  // The point functions are finite for J <= 0 (tests above), but dipc keeps every element
  // uninverted: the element reports det F <= 0 as neo-Hookean does.
  std::mt19937_64 rng(46);
  const Nodes X = test::distorted_hex(rng, 1.0, 0.1);
  Nodes mirrored = X;
  for (int a = 0; a < 8; ++a) mirrored[3 * a] = -X[3 * a];
  double lambda, mu, e, g[24], H[576];
  lame_parameters(1e6, 0.3, &lambda, &mu);
  EXPECT_FALSE(kElement(X.data(), mirrored.data(), lambda, mu, &e, g, H));
  EXPECT_FALSE(hex8_elastic(VolumetricTerm::gauss_points, MaterialModel::stable_neo_hookean, X.data(), mirrored.data(),
                            lambda, mu, &e, g, H));
}

TEST(Hex8StableNeoHookean, DispatchSelectsTheMaterial) {
  for (const ElementCase& c : element_cases(47)) {
    double e_nh, e_snh, e_nh_d, e_snh_d;
    ASSERT_TRUE(hex8_neo_hookean(c.X.data(), c.x.data(), c.lambda, c.mu, &e_nh, nullptr, nullptr));
    ASSERT_TRUE(kElement(c.X.data(), c.x.data(), c.lambda, c.mu, &e_snh, nullptr, nullptr));
    ASSERT_TRUE(hex8_elastic(VolumetricTerm::gauss_points, MaterialModel::neo_hookean, c.X.data(), c.x.data(), c.lambda,
                             c.mu, &e_nh_d, nullptr, nullptr));
    ASSERT_TRUE(hex8_elastic(VolumetricTerm::gauss_points, MaterialModel::stable_neo_hookean, c.X.data(), c.x.data(),
                             c.lambda, c.mu, &e_snh_d, nullptr, nullptr));
    EXPECT_EQ(e_nh_d, e_nh);
    EXPECT_EQ(e_snh_d, e_snh);
    if (std::abs(e_nh) > 1e-6 * c.mu) {
      EXPECT_NE(e_nh, e_snh);  // large strains: different materials
    }
  }
}

}  // namespace
}  // namespace dipc
