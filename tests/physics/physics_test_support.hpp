// Shared helpers for the assembly unit tests: seeded random rotations, deformation
// gradients with prescribed singular values, distorted hex8 elements, and dense-matrix
// checks. Independent of the code under test (rotations come from Gram-Schmidt, not from
// the SVD or Jacobi routines being tested).
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <vector>

#include "math/small_matrix.hpp"
#include "mesh/hex8_reference.hpp"
#include "support/finite_difference.hpp"

namespace dipc::test {

using Mat3 = std::array<double, 9>;

inline Mat3 multiply(const Mat3& A, const Mat3& B) {
  Mat3 C{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) C[3 * i + j] += A[3 * i + k] * B[3 * k + j];
  return C;
}

// Uniformly random proper rotation: Gram-Schmidt of a Gaussian matrix, det fixed to +1.
inline Mat3 random_rotation(std::mt19937_64& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  double c[3][3];
  for (auto& v : c)
    for (double& s : v) s = n(rng);
  for (int k = 0; k < 3; ++k) {
    for (int j = 0; j < k; ++j) {
      const double d = c[k][0] * c[j][0] + c[k][1] * c[j][1] + c[k][2] * c[j][2];
      for (int i = 0; i < 3; ++i) c[k][i] -= d * c[j][i];
    }
    const double nn = std::sqrt(c[k][0] * c[k][0] + c[k][1] * c[k][1] + c[k][2] * c[k][2]);
    for (int i = 0; i < 3; ++i) c[k][i] /= nn;
  }
  Mat3 R;
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) R[3 * i + k] = c[k][i];
  if (det3x3(R.data()) < 0)
    for (int i = 0; i < 3; ++i) R[3 * i + 2] = -R[3 * i + 2];
  return R;
}

// F = R1 diag(s) R2 with det F = J: random stretch directions, then scaled to the target J.
inline Mat3 random_deformation_gradient(std::mt19937_64& rng, double J, double anisotropy,
                                        double* min_singular_value = nullptr) {
  std::normal_distribution<double> n(0.0, anisotropy);
  double s[3] = {std::exp(n(rng)), std::exp(n(rng)), std::exp(n(rng))};
  const double scale = std::cbrt(J / (s[0] * s[1] * s[2]));
  for (double& v : s) v *= scale;
  if (min_singular_value) *min_singular_value = std::min({s[0], s[1], s[2]});
  const Mat3 D = {s[0], 0, 0, 0, s[1], 0, 0, 0, s[2]};
  return multiply(multiply(random_rotation(rng), D), random_rotation(rng));
}

// Unit cube in hex8 node order, scaled by `size`, every corner moved by up to
// `distortion*size` per coordinate: faces are generally non-planar (not a parallelepiped).
inline std::array<double, 24> distorted_hex(std::mt19937_64& rng, double size, double distortion) {
  std::uniform_real_distribution<double> u(-distortion, distortion);
  std::array<double, 24> X;
  for (int a = 0; a < 8; ++a) {
    X[3 * a] = size * (0.5 * (1 + hex8::corner_xi(a)) + u(rng));
    X[3 * a + 1] = size * (0.5 * (1 + hex8::corner_eta(a)) + u(rng));
    X[3 * a + 2] = size * (0.5 * (1 + hex8::corner_zeta(a)) + u(rng));
  }
  return X;
}

// x = A X + t + noise per node, with A a random deformation gradient of determinant J.
inline std::array<double, 24> deformed_hex(std::mt19937_64& rng, const std::array<double, 24>& X, double J,
                                           double anisotropy, double noise) {
  const Mat3 A = random_deformation_gradient(rng, J, anisotropy);
  std::uniform_real_distribution<double> u(-noise, noise);
  std::array<double, 24> x;
  for (int a = 0; a < 8; ++a)
    for (int i = 0; i < 3; ++i)
      x[3 * a + i] = A[3 * i] * X[3 * a] + A[3 * i + 1] * X[3 * a + 1] + A[3 * i + 2] * X[3 * a + 2] + 0.3 * i + u(rng);
  return x;
}

inline double max_abs(const double* v, int n) {
  double m = 0;
  for (int i = 0; i < n; ++i) m = std::max(m, std::abs(v[i]));
  return m;
}

inline double max_abs_difference(const double* a, const double* b, int n) {
  double m = 0;
  for (int i = 0; i < n; ++i) m = std::max(m, std::abs(a[i] - b[i]));
  return m;
}

inline double max_asymmetry(const double* A, int n) {
  double m = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) m = std::max(m, std::abs(A[n * i + j] - A[n * j + i]));
  return m;
}

// Central differences (tests/support/finite_difference.hpp), step h, of an element function
// with the signature of hex8_neo_hookean(X, x, lambda, mu, energy, gradient, hessian): the
// gradient of its energy (24) and the Jacobian of its gradient (24x24, row-major). False if a
// perturbed state fails.
template <class Element>
bool central_difference_gradient(Element element, const std::array<double, 24>& X, const std::array<double, 24>& x,
                                 double lambda, double mu, double h, double g_fd[24]) {
  const auto energy = [&](const double* y, double* e) { return element(X.data(), y, lambda, mu, e, nullptr, nullptr); };
  return central_difference(energy, x.data(), 24, 1, h, g_fd);
}

template <class Element>
bool central_difference_hessian(Element element, const std::array<double, 24>& X, const std::array<double, 24>& x,
                                double lambda, double mu, double h, double H_fd[576]) {
  const auto gradient = [&](const double* y, double* g) {
    return element(X.data(), y, lambda, mu, nullptr, g, nullptr);
  };
  return central_difference(gradient, x.data(), 24, 24, h, H_fd);
}

}  // namespace dipc::test
