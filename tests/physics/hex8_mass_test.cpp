// Tests of the hex8 mass matrices: total mass against the exact volume of a trilinear hex
// (closed-form polynomial integration, no quadrature), consistency of lumped and consistent
// masses, and the textbook consistent mass of a box.
#include "physics/hex8_mass.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>

#include "physics_test_support.hpp"

namespace dipc {
namespace {

using Nodes = std::array<double, 24>;

// Exact volume of the trilinear hex: write x(xi,eta,zeta) = sum_pqr c_pqr xi^p eta^q zeta^r
// (p,q,r in {0,1}, c_pqr = sum_a x_a s_a^p t_a^q u_a^r / 8 with (s,t,u) the corner signs),
// expand det J = x_xi . (x_eta x x_zeta) into monomials and integrate each exactly over
// [-1,1]^3 (int xi^n = 2/(n+1) for even n, 0 for odd n).
double exact_trilinear_volume(const Nodes& X) {
  double c[2][2][2][3] = {};
  for (int a = 0; a < 8; ++a) {
    const double s[2][3] = {{1, 1, 1}, {hex8::corner_xi(a), hex8::corner_eta(a), hex8::corner_zeta(a)}};
    for (int p = 0; p < 2; ++p)
      for (int q = 0; q < 2; ++q)
        for (int r = 0; r < 2; ++r)
          for (int i = 0; i < 3; ++i) c[p][q][r][i] += X[3 * a + i] * s[p][0] * s[q][1] * s[r][2] / 8;
  }
  auto integral = [](int n) { return n % 2 ? 0.0 : 2.0 / (n + 1); };
  double volume = 0;
  // x_xi term c[1][q1][r1] eta^q1 zeta^r1, x_eta term c[p2][1][r2] xi^p2 zeta^r2,
  // x_zeta term c[p3][q3][1] xi^p3 eta^q3.
  for (int q1 = 0; q1 < 2; ++q1)
    for (int r1 = 0; r1 < 2; ++r1)
      for (int p2 = 0; p2 < 2; ++p2)
        for (int r2 = 0; r2 < 2; ++r2)
          for (int p3 = 0; p3 < 2; ++p3)
            for (int q3 = 0; q3 < 2; ++q3) {
              const double* a = c[1][q1][r1];
              const double* b = c[p2][1][r2];
              const double* d = c[p3][q3][1];
              const double triple = a[0] * (b[1] * d[2] - b[2] * d[1]) - a[1] * (b[0] * d[2] - b[2] * d[0]) +
                                    a[2] * (b[0] * d[1] - b[1] * d[0]);
              volume += triple * integral(p2 + p3) * integral(q1 + q3) * integral(r1 + r2);
            }
  return volume;
}

TEST(Hex8Mass, ExactVolumeFormulaOfBoxIsProductOfSides) {
  Nodes X;
  for (int a = 0; a < 8; ++a) {
    X[3 * a] = 2.0 * (hex8::corner_xi(a) > 0);
    X[3 * a + 1] = 3.0 * (hex8::corner_eta(a) > 0);
    X[3 * a + 2] = 0.5 * (hex8::corner_zeta(a) > 0);
  }
  EXPECT_NEAR(exact_trilinear_volume(X), 3.0, 1e-14);
}

TEST(Hex8Mass, LumpedMassSumsToDensityTimesExactVolumeOfDistortedHex) {
  std::mt19937_64 rng(31);
  for (int k = 0; k < 20; ++k) {
    const Nodes X = test::distorted_hex(rng, 0.5 + k, 0.2);
    const double rho = 1000.0 + 10 * k;
    double m[8];
    hex8_lumped_mass(X.data(), rho, m);
    double total = 0;
    for (double v : m) {
      EXPECT_GT(v, 0.0);
      total += v;
    }
    const double volume = exact_trilinear_volume(X);
    EXPECT_NEAR(total, rho * volume, 1e-12 * rho * volume);
  }
}

TEST(Hex8Mass, ConsistentMassRowsSumToLumpedMass) {
  std::mt19937_64 rng(32);
  for (int k = 0; k < 10; ++k) {
    const Nodes X = test::distorted_hex(rng, 1.0, 0.2);
    double M[64], m[8];
    hex8_consistent_mass(X.data(), 7.5, M);
    hex8_lumped_mass(X.data(), 7.5, m);
    for (int a = 0; a < 8; ++a) {
      double row = 0;
      for (int b = 0; b < 8; ++b) {
        row += M[8 * a + b];
        EXPECT_EQ(M[8 * a + b], M[8 * b + a]);
      }
      EXPECT_NEAR(row, m[a], 1e-14 * m[a] * 8);
    }
  }
}

TEST(Hex8Mass, ConsistentMassOfBoxMatchesTextbook) {
  // For a box of volume V, M_ab = rho V / 27 * 2^-d with d the number of coordinates in
  // which corners a and b differ (1D element mass h/6 [2 1; 1 2] in each direction), which
  // 2x2x2 Gauss integrates exactly.
  Nodes X;
  for (int a = 0; a < 8; ++a) {
    X[3 * a] = 1.0 + 2.0 * (hex8::corner_xi(a) > 0);
    X[3 * a + 1] = 0.5 * (hex8::corner_eta(a) > 0);
    X[3 * a + 2] = 4.0 * (hex8::corner_zeta(a) > 0);
  }
  const double rho = 3.0, V = 4.0;
  double M[64];
  hex8_consistent_mass(X.data(), rho, M);
  for (int a = 0; a < 8; ++a)
    for (int b = 0; b < 8; ++b) {
      const int d = (hex8::corner_xi(a) != hex8::corner_xi(b)) + (hex8::corner_eta(a) != hex8::corner_eta(b)) +
                    (hex8::corner_zeta(a) != hex8::corner_zeta(b));
      EXPECT_NEAR(M[8 * a + b], rho * V / 27 / (1 << d), 1e-14) << a << "," << b;
    }
}

}  // namespace
}  // namespace dipc
