// Compressible neo-Hookean material at a quadrature point (DESIGN.md section 1; the form
// used by the IPC paper and PolyFEM):
//   psi(F) = mu/2 (tr F^T F - 3) - mu ln J + lambda/2 (ln J)^2,   J = det F > 0,
// its first Piola-Kirchhoff stress P = d psi/dF, the exact 9x9 tangent dP/dF and the tangent
// projected to positive semi-definite through its analytic eigensystem. F and P are
// flattened row-major (k = 3i + j <-> F_ij); dPdF[9k + l] = dP_k/dF_l. All functions assume
// J > 0: inverted states are rejected by the callers before they get here.
#pragma once
#include <cmath>

#include "assembly/small_matrix.hpp"
#include "assembly/symmetric_eigen.hpp"
#include "host_device.hpp"

namespace dipc {

// Lame parameters from Young's modulus and Poisson's ratio (isotropic linear elasticity).
DIPC_HD void lame_parameters(double E, double nu, double* lambda, double* mu) {
  *lambda = E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
  *mu = E / (2.0 * (1.0 + nu));
}

DIPC_HD double neo_hookean_energy(const double F[9], double lambda, double mu) {
  const double log_J = log(det3x3(F));
  return 0.5 * mu * (double_contraction3x3(F, F) - 3.0) - mu * log_J + 0.5 * lambda * log_J * log_J;
}

// P = mu F + (lambda ln J - mu) F^{-T}, using d(ln J)/dF = F^{-T}.
DIPC_HD void neo_hookean_stress(const double F[9], double lambda, double mu, double P[9]) {
  double FinvT[9];
  const double J = inverse_transpose3x3(F, FinvT);
  const double c = lambda * log(J) - mu;
  for (int k = 0; k < 9; ++k) P[k] = mu * F[k] + c * FinvT[k];
}

// dP_ij/dF_kl = mu d_ik d_jl + lambda F^{-T}_ij F^{-T}_kl - (lambda ln J - mu) F^{-1}_jk F^{-1}_li,
// from d(F^{-T})_ij/dF_kl = -F^{-1}_jk F^{-1}_li. Written exactly symmetric (it is the
// Hessian of psi).
DIPC_HD void neo_hookean_stress_derivative(const double F[9], double lambda, double mu, double dPdF[81]) {
  double Finv[9];
  const double J = inverse3x3(F, Finv);
  const double c = lambda * log(J) - mu;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      const int r = 3 * i + j;
      for (int k = 0; k < 3; ++k)
        for (int l = 0; l < 3; ++l) {
          const int s = 3 * k + l;
          if (s < r) continue;
          double v = lambda * Finv[3 * j + i] * Finv[3 * l + k] + c * Finv[3 * j + k] * Finv[3 * l + i];
          if (r == s) v += mu;
          dPdF[9 * r + s] = dPdF[9 * s + r] = v;
        }
    }
}

// Singular value decomposition F = U diag(sigma) V^T with U, V proper rotations, for
// det F > 0 (then all sigma_i > 0). V comes from the Jacobi eigenvectors of F^T F (sorted
// by decreasing eigenvalue, last column flipped if needed so det V = +1); U from the
// Gram-Schmidt QR of F V, whose diagonal gives sigma. Orthogonalising F V instead of
// dividing by sigma keeps U orthonormal to rounding even when singular values coincide.
DIPC_HD void rotation_variant_svd(const double F[9], double U[9], double sigma[3], double V[9]) {
  double C[9], w[3], E[9];
  multiply_transpose_a3x3(F, F, C);
  symmetric_eigen<3>(C, 3, w, E);
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) V[3 * i + k] = E[3 * i + (2 - k)];
  if (det3x3(V) < 0)
    for (int i = 0; i < 3; ++i) V[3 * i + 2] = -V[3 * i + 2];
  double B[9];
  multiply3x3(F, V, B);
  double u0[3], u1[3];
  const double n0 = sqrt(B[0] * B[0] + B[3] * B[3] + B[6] * B[6]);
  for (int i = 0; i < 3; ++i) u0[i] = B[3 * i] / n0;
  const double d01 = u0[0] * B[1] + u0[1] * B[4] + u0[2] * B[7];
  for (int i = 0; i < 3; ++i) u1[i] = B[3 * i + 1] - d01 * u0[i];
  const double n1 = sqrt(u1[0] * u1[0] + u1[1] * u1[1] + u1[2] * u1[2]);
  for (int i = 0; i < 3; ++i) u1[i] /= n1;
  const double u2[3] = {u0[1] * u1[2] - u0[2] * u1[1], u0[2] * u1[0] - u0[0] * u1[2],
                        u0[0] * u1[1] - u0[1] * u1[0]};
  for (int i = 0; i < 3; ++i) {
    U[3 * i + 0] = u0[i];
    U[3 * i + 1] = u1[i];
    U[3 * i + 2] = u2[i];
  }
  sigma[0] = n0;
  sigma[1] = u1[0] * B[1] + u1[1] * B[4] + u1[2] * B[7];
  sigma[2] = u2[0] * B[2] + u2[1] * B[5] + u2[2] * B[8];
}

// dP/dF rebuilt from its analytic eigensystem (Smith, de Goes & Kim 2019, "Analytic
// eigensystems for isotropic distortion energies", ACM TOG 38(1), sections 4-5), with the
// eigenvalues clamped at 0 when `clamp` is true. With F = U S V^T and psi isotropic, every
// eigenvector is U D V^T for a 3x3 D:
//  - scaling: D = diag(z), z an eigenvector of the 3x3 Hessian d2psi/dsigma_i dsigma_j,
//    here A_ii = mu + (lambda (1 - ln J) + mu) / sigma_i^2, A_ij = lambda / (sigma_i sigma_j);
//  - for each pair i < j, with c = lambda ln J - mu and psi_i = mu sigma_i + c / sigma_i:
//    the symmetric ("flip") D = (e_i e_j^T + e_j e_i^T)/sqrt2 with eigenvalue
//    (psi_i - psi_j)/(sigma_i - sigma_j) = mu - c/(sigma_i sigma_j), and the antisymmetric
//    ("twist", infinitesimal rotation) D = (e_i e_j^T - e_j e_i^T)/sqrt2 with eigenvalue
//    (psi_i + psi_j)/(sigma_i + sigma_j) = mu + c/(sigma_i sigma_j). Both closed forms avoid
//    dividing by sigma_i - sigma_j. (At F = I the twists have eigenvalue 0: rotations.)
// The scaling block is clamped by projecting the 3x3 A, which is the same as clamping its
// eigenvalues. The outer products are sign-invariant, so no eigenvector sign convention
// matters; the row-major flattening of U D V^T is the vector dotted with vec(dF).
DIPC_HD void neo_hookean_stress_derivative_eigensystem(const double F[9], double lambda, double mu,
                                                       bool clamp, double dPdF[81]) {
  double U[9], s[3], V[9];
  rotation_variant_svd(F, U, s, V);
  const double log_J = log(s[0] * s[1] * s[2]);
  const double c = lambda * log_J - mu;
  double A[9];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      A[3 * i + j] = i == j ? mu + (lambda * (1.0 - log_J) + mu) / (s[i] * s[i]) : lambda / (s[i] * s[j]);
  if (clamp) project_psd<3>(A, 3);
  // Outer-product basis vec(u_i v_j^T)_(3a+b) = U_ai V_bj; D_i = vec(u_i v_i^T).
  double D[3][9];
  for (int i = 0; i < 3; ++i)
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) D[i][3 * a + b] = U[3 * a + i] * V[3 * b + i];
  // Pair modes (i,j) = (0,1), (0,2), (1,2): flip and twist vectors and their eigenvalues.
  double Q[6][9], ev[6];
  const double inv_sqrt2 = 0.70710678118654752440;
  int m = 0;
  for (int i = 0; i < 2; ++i)
    for (int j = i + 1; j < 3; ++j, m += 2) {
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) {
          const double ij = U[3 * a + i] * V[3 * b + j], ji = U[3 * a + j] * V[3 * b + i];
          Q[m][3 * a + b] = inv_sqrt2 * (ij + ji);
          Q[m + 1][3 * a + b] = inv_sqrt2 * (ij - ji);
        }
      const double r = c / (s[i] * s[j]);
      ev[m] = mu - r;
      ev[m + 1] = mu + r;
      if (clamp) {
        ev[m] = ev[m] > 0 ? ev[m] : 0.0;
        ev[m + 1] = ev[m + 1] > 0 ? ev[m + 1] : 0.0;
      }
    }
  for (int r = 0; r < 9; ++r)
    for (int t = r; t < 9; ++t) {
      double v = 0;
      for (int i = 0; i < 3; ++i) {
        const double Ai_t = A[3 * i] * D[0][t] + A[3 * i + 1] * D[1][t] + A[3 * i + 2] * D[2][t];
        v += D[i][r] * Ai_t;
      }
      for (int k = 0; k < 6; ++k) v += ev[k] * Q[k][r] * Q[k][t];
      dPdF[9 * r + t] = dPdF[9 * t + r] = v;
    }
}

// dP/dF projected to positive semi-definite (negative eigenvalues of the analytic
// eigensystem clamped to 0), for the Newton Hessian.
DIPC_HD void neo_hookean_stress_derivative_psd(const double F[9], double lambda, double mu, double dPdF[81]) {
  neo_hookean_stress_derivative_eigensystem(F, lambda, mu, true, dPdF);
}

}  // namespace dipc
