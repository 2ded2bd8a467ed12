// Tests of the cyclic Jacobi eigen-solver and project_psd on matrices with known spectra.
#include "math/symmetric_eigen.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

#include "physics_test_support.hpp"

namespace dipc {
namespace {

// Random orthogonal n x n matrix (Gram-Schmidt of a Gaussian matrix), row-major.
std::vector<double> random_orthogonal(std::mt19937_64& rng, int n) {
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<double> Q(n * n);
  for (double& v : Q) v = g(rng);
  for (int k = 0; k < n; ++k) {
    for (int pass = 0; pass < 2; ++pass)
      for (int j = 0; j < k; ++j) {
        double d = 0;
        for (int i = 0; i < n; ++i) d += Q[n * i + k] * Q[n * i + j];
        for (int i = 0; i < n; ++i) Q[n * i + k] -= d * Q[n * i + j];
      }
    double nn = 0;
    for (int i = 0; i < n; ++i) nn += Q[n * i + k] * Q[n * i + k];
    for (int i = 0; i < n; ++i) Q[n * i + k] /= std::sqrt(nn);
  }
  return Q;
}

// Q diag(d) Q^T
std::vector<double> with_spectrum(const std::vector<double>& Q, const std::vector<double>& d) {
  const int n = static_cast<int>(d.size());
  std::vector<double> A(n * n, 0.0);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) A[n * i + j] += Q[n * i + k] * d[k] * Q[n * j + k];
  return A;
}

class SymmetricEigenTest : public ::testing::TestWithParam<int> {};

TEST_P(SymmetricEigenTest, RecoversKnownSpectrumAndOrthonormalVectors) {
  const int n = GetParam();
  std::mt19937_64 rng(1000 + n);
  std::uniform_real_distribution<double> u(-10.0, 10.0);
  for (int trial = 0; trial < 20; ++trial) {
    std::vector<double> d(n);
    for (double& v : d) v = u(rng);
    if (trial % 4 == 0) d[0] = d[n - 1];  // a repeated eigenvalue
    const auto A = with_spectrum(random_orthogonal(rng, n), d);
    std::vector<double> w(n), V(n * n);
    ASSERT_GT(symmetric_eigen(A.data(), n, w.data(), V.data()), 0);
    std::sort(d.begin(), d.end());
    for (int k = 0; k < n; ++k) EXPECT_NEAR(w[k], d[k], 1e-12 * 10) << "n=" << n << " k=" << k;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        double vtv = 0, avw = 0;
        for (int k = 0; k < n; ++k) {
          vtv += V[n * k + i] * V[n * k + j];
          avw += A[n * i + k] * V[n * k + j];
        }
        EXPECT_NEAR(vtv, i == j ? 1.0 : 0.0, 1e-13);
        EXPECT_NEAR(avw, w[j] * V[n * i + j], 1e-11);  // A v_j = w_j v_j
      }
  }
}

TEST_P(SymmetricEigenTest, ProjectPsdClampsOnlyNegativeEigenvalues) {
  const int n = GetParam();
  std::mt19937_64 rng(2000 + n);
  std::uniform_real_distribution<double> u(-5.0, 5.0);
  for (int trial = 0; trial < 20; ++trial) {
    std::vector<double> d(n);
    for (double& v : d) v = u(rng);
    const auto Q = random_orthogonal(rng, n);
    auto A = with_spectrum(Q, d);
    std::vector<double> clamped(d);
    for (double& v : clamped) v = std::max(v, 0.0);
    const auto expected = with_spectrum(Q, clamped);
    project_psd(A.data(), n);
    EXPECT_LT(test::max_abs_difference(A.data(), expected.data(), n * n), 1e-12 * 5 * n);
    EXPECT_EQ(test::max_asymmetry(A.data(), n), 0.0);
    std::vector<double> w(n), V(n * n);
    symmetric_eigen(A.data(), n, w.data(), V.data());
    EXPECT_GE(w[0], -1e-12 * 5);
  }
}

TEST_P(SymmetricEigenTest, ProjectPsdLeavesPsdMatrixUnchanged) {
  const int n = GetParam();
  std::mt19937_64 rng(3000 + n);
  std::normal_distribution<double> g(0.0, 1.0);
  for (int trial = 0; trial < 10; ++trial) {
    // B B^T with B n x (n-2): PSD with two zero eigenvalues.
    const int m = n - 2;
    std::vector<double> B(n * m), A(n * n, 0.0);
    for (double& v : B) v = g(rng);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j)
        for (int k = 0; k < m; ++k) A[n * i + j] += B[m * i + k] * B[m * j + k];
    auto P = A;
    project_psd(P.data(), n);
    EXPECT_LT(test::max_abs_difference(P.data(), A.data(), n * n), 1e-12 * test::max_abs(A.data(), n * n));
  }
}

INSTANTIATE_TEST_SUITE_P(Sizes, SymmetricEigenTest, ::testing::Values(3, 6, 9, 12));

TEST(SymmetricEigen, DiagonalAndZeroMatricesNeedNoRotation) {
  const double A[9] = {3, 0, 0, 0, -1, 0, 0, 0, 2};
  double w[3], V[9];
  EXPECT_EQ(symmetric_eigen(A, 3, w, V), 1);
  EXPECT_EQ(w[0], -1.0);
  EXPECT_EQ(w[1], 2.0);
  EXPECT_EQ(w[2], 3.0);
  const double Z[4] = {0, 0, 0, 0};
  double wz[2], Vz[4];
  EXPECT_EQ(symmetric_eigen(Z, 2, wz, Vz), 1);
  EXPECT_EQ(wz[0], 0.0);
  EXPECT_EQ(wz[1], 0.0);
}

}  // namespace
}  // namespace dipc
