// Cyclic Jacobi eigen-decomposition of small symmetric matrices (n <= 12) and the
// projection of a symmetric matrix onto the positive semi-definite cone. Host/device point
// functions on plain row-major arrays: used for the 3x3 SVD of the deformation gradient,
// as the reference projection in tests, and for contact Hessians (9x9, after their
// translations are taken out: contact/geometry/translation_free_psd.hpp).
#pragma once
#include <cmath>

#include "math/host_device.hpp"

namespace dipc {

constexpr int kSymmetricEigenMaxN = 12;

// Eigen-decomposition A = V diag(w) V^T of the symmetric n x n row-major matrix A
// (only its upper triangle is read). Eigenvalues w come sorted ascending; V is row-major
// with eigenvector k in column k (V[n*i + k]). MaxN bounds n at compile time so the work
// copy lives on the stack. Returns the number of sweeps, or -1 if 64 sweeps did not
// converge (the result is then still the best estimate).
//
// Cyclic-by-row Jacobi with the stable symmetric Schur rotation (Golub & Van Loan, Matrix
// Computations, 4th ed., section 8.5 "Jacobi methods"). With EigenAccuracy::relative a pair
// (p,q) is rotated while |a_pq| > eps * sqrt(|a_pp a_qq|), the criterion of Demmel & Veselic
// (1992), which gives small eigenvalues of positive definite matrices (such as F^T F of a
// compressed element) to high relative accuracy; pairs below 1e-300 * ||A|| are ignored so
// indefinite matrices with zero diagonal still terminate. With EigenAccuracy::absolute a
// pair is rotated while |a_pq| > 8 eps ||A||_F: every eigenvalue to a few eps ||A||, which is
// all a PSD projection needs, in about two thirds of the sweeps on rank-deficient matrices
// such as contact Hessians (whose small diagonal entries keep the relative test rotating).
enum class EigenAccuracy { relative, absolute };
template <int MaxN = kSymmetricEigenMaxN>
DIPC_HD int symmetric_eigen(const double* A, int n, double* w, double* V,
                            EigenAccuracy accuracy = EigenAccuracy::relative) {
  double a[MaxN * MaxN];
  double norm2 = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const double v = i <= j ? A[n * i + j] : A[n * j + i];
      a[n * i + j] = v;
      norm2 += v * v;
      V[n * i + j] = i == j ? 1.0 : 0.0;
    }
  const double eps = 2.220446049250313e-16;
  const double floor_value = accuracy == EigenAccuracy::relative ? 1e-300 * sqrt(norm2) : 8 * eps * sqrt(norm2);
  int sweeps = -1;
  for (int sweep = 1; sweep <= 64; ++sweep) {
    bool rotated = false;
    for (int p = 0; p < n - 1; ++p)
      for (int q = p + 1; q < n; ++q) {
        const double apq = a[n * p + q];
        const double app = a[n * p + p], aqq = a[n * q + q];
        const double mag = fabs(apq);
        if (mag <= floor_value || (accuracy == EigenAccuracy::relative && mag <= eps * sqrt(fabs(app * aqq))))
          continue;
        rotated = true;
        const double tau = (aqq - app) / (2.0 * apq);
        const double t = fabs(tau) > 1e150 ? 0.5 / tau : (tau >= 0 ? 1.0 : -1.0) / (fabs(tau) + sqrt(1.0 + tau * tau));
        const double c = 1.0 / sqrt(1.0 + t * t);
        const double s = t * c;
        // A <- J^T A J with J the (p,q) rotation [c s; -s c]; a_pq becomes exactly 0.
        for (int k = 0; k < n; ++k) {
          if (k == p || k == q) continue;
          const double akp = a[n * k + p], akq = a[n * k + q];
          const double nkp = c * akp - s * akq, nkq = s * akp + c * akq;
          a[n * k + p] = a[n * p + k] = nkp;
          a[n * k + q] = a[n * q + k] = nkq;
        }
        a[n * p + p] = app - t * apq;
        a[n * q + q] = aqq + t * apq;
        a[n * p + q] = a[n * q + p] = 0.0;
        for (int k = 0; k < n; ++k) {
          const double vkp = V[n * k + p], vkq = V[n * k + q];
          V[n * k + p] = c * vkp - s * vkq;
          V[n * k + q] = s * vkp + c * vkq;
        }
      }
    if (!rotated) {
      sweeps = sweep;
      break;
    }
  }
  for (int i = 0; i < n; ++i) w[i] = a[n * i + i];
  // Selection sort of the eigenpairs, ascending (n is tiny).
  for (int i = 0; i < n - 1; ++i) {
    int m = i;
    for (int j = i + 1; j < n; ++j)
      if (w[j] < w[m]) m = j;
    if (m == i) continue;
    const double tw = w[i];
    w[i] = w[m];
    w[m] = tw;
    for (int k = 0; k < n; ++k) {
      const double tv = V[n * k + i];
      V[n * k + i] = V[n * k + m];
      V[n * k + m] = tv;
    }
  }
  return sweeps;
}

// Replaces the symmetric n x n matrix A by its nearest positive semi-definite matrix in the
// Frobenius norm, V diag(max(w, 0)) V^T (Higham 1988). The output is exactly symmetric.
template <int MaxN = kSymmetricEigenMaxN>
DIPC_HD void project_psd(double* A, int n, EigenAccuracy accuracy = EigenAccuracy::relative) {
  double w[MaxN], V[MaxN * MaxN];
  symmetric_eigen<MaxN>(A, n, w, V, accuracy);
  for (int k = 0; k < n; ++k) w[k] = w[k] > 0 ? w[k] : 0.0;
  for (int i = 0; i < n; ++i)
    for (int j = i; j < n; ++j) {
      double s = 0;
      for (int k = 0; k < n; ++k) s += V[n * i + k] * w[k] * V[n * j + k];
      A[n * i + j] = A[n * j + i] = s;
    }
}

}  // namespace dipc
