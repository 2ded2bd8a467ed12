// The eigensystem of the tangent dP/dF of an isotropic hyperelastic energy psi(F) and the
// projection of that tangent to positive semi-definite (Smith, de Goes & Kim 2019, "Analytic
// eigensystems for isotropic distortion energies", ACM Trans. Graph. 38(1)). With F = U S V^T
// (rotation-variant SVD, U and V proper rotations) every eigenvector of dP/dF is vec(U D V^T):
//  - scaling modes D = diag(z), z an eigenvector of the 3x3 Hessian A_ij = d2psi/dsigma_i dsigma_j;
//  - for each pair i < j, with psi_i = dpsi/dsigma_i: the "flip" D = (e_i e_j^T + e_j e_i^T)/sqrt2
//    with eigenvalue (psi_i - psi_j)/(sigma_i - sigma_j) and the "twist"
//    D = (e_i e_j^T - e_j e_i^T)/sqrt2 with eigenvalue (psi_i + psi_j)/(sigma_i + sigma_j).
// Each material fills an IsotropicEigensystem with its closed forms of A and of the six pair
// eigenvalues (neo_hookean.hpp, stable_neo_hookean.hpp, hex8_mean_dilatation.hpp);
// add_psd_correction then projects its exact tangent.
#pragma once
#include <cmath>

#include "math/host_device.hpp"
#include "math/small_matrix.hpp"
#include "math/symmetric_eigen.hpp"

namespace dipc {

// Singular value decomposition F = U diag(sigma) V^T with U, V proper rotations. For
// det F > 0 all sigma_i > 0; for det F <= 0 (F of rank >= 2) sigma_2, the smallest in
// magnitude, carries the sign of det F (the columns of F V are orthogonal, so F V =
// U diag(sigma)). V comes from the Jacobi eigenvectors of F^T F (sorted by decreasing
// eigenvalue, last column flipped if needed so det V = +1); U from the Gram-Schmidt QR of
// F V, whose diagonal gives sigma. Orthogonalising F V instead of
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
  const double u2[3] = {u0[1] * u1[2] - u0[2] * u1[1], u0[2] * u1[0] - u0[0] * u1[2], u0[0] * u1[1] - u0[1] * u1[0]};
  for (int i = 0; i < 3; ++i) {
    U[3 * i + 0] = u0[i];
    U[3 * i + 1] = u1[i];
    U[3 * i + 2] = u2[i];
  }
  sigma[0] = n0;
  sigma[1] = u1[0] * B[1] + u1[1] * B[4] + u1[2] * B[7];
  sigma[2] = u2[0] * B[2] + u2[1] * B[5] + u2[2] * B[8];
}

// Pair modes are ordered (0,1), (0,2), (1,2), flip before twist.
struct IsotropicEigensystem {
  double U[9], sigma[3], V[9];
  double scaling_hessian[9];   // A above, row-major 3x3
  double pair_eigenvalues[6];  // flip, twist for each pair
};

namespace detail {

// vec(u_i v_i^T) for i = 0..2 (row-major flattening: entry 3a + b is U_ai V_bi).
DIPC_HD void scaling_basis(const IsotropicEigensystem& es, double D[3][9]) {
  for (int i = 0; i < 3; ++i)
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) D[i][3 * a + b] = es.U[3 * a + i] * es.V[3 * b + i];
}

// Flip (m even) or twist (m odd) eigenvector of pair mode m, flattened row-major.
DIPC_HD void pair_mode(const IsotropicEigensystem& es, int m, double q[9]) {
  const int pair = m / 2;
  const int i = pair == 2 ? 1 : 0, j = pair == 0 ? 1 : 2;
  const double sign = (m % 2) ? -1.0 : 1.0;
  const double inv_sqrt2 = 0.70710678118654752440;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b)
      q[3 * a + b] = inv_sqrt2 * (es.U[3 * a + i] * es.V[3 * b + j] + sign * es.U[3 * a + j] * es.V[3 * b + i]);
}

// H += sum_ij S_ij D_i D_j^T (upper triangle only) for the symmetric 3x3 S.
DIPC_HD void add_scaling_block(const double D[3][9], const double S[9], double H[81]) {
  for (int r = 0; r < 9; ++r) {
    const double SDr[3] = {S[0] * D[0][r] + S[1] * D[1][r] + S[2] * D[2][r],
                           S[3] * D[0][r] + S[4] * D[1][r] + S[5] * D[2][r],
                           S[6] * D[0][r] + S[7] * D[1][r] + S[8] * D[2][r]};
    for (int t = r; t < 9; ++t) H[9 * r + t] += SDr[0] * D[0][t] + SDr[1] * D[1][t] + SDr[2] * D[2][t];
  }
}

// H += w q q^T (upper triangle only).
DIPC_HD void add_rank_one(double w, const double q[9], double H[81]) {
  for (int r = 0; r < 9; ++r) {
    const double wq = w * q[r];
    for (int t = r; t < 9; ++t) H[9 * r + t] += wq * q[t];
  }
}

DIPC_HD void mirror_upper(double H[81]) {
  for (int r = 0; r < 9; ++r)
    for (int t = r + 1; t < 9; ++t) H[9 * t + r] = H[9 * r + t];
}

}  // namespace detail

// Adds to an exact tangent dPdF the correction that projects it to positive semi-definite:
// minus its negative part, -sum_{lambda_k < 0} lambda_k q_k q_k^T, which equals clamping the
// negative eigenvalues to 0 but only touches the (few) negative modes. The scaling block is
// corrected by (proj(A) - A) only when A is not positive semi-definite (checked through its
// leading principal minors / a 3x3 Jacobi solve). Works for any isotropic energy whose
// eigensystem `es` describes dPdF (neo_hookean_eigensystem, mean_dilatation_eigensystem).
DIPC_HD void add_psd_correction(const IsotropicEigensystem& es, double dPdF[81]) {
  const double* A = es.scaling_hessian;
  const double minor2 = A[0] * A[4] - A[1] * A[3];
  const bool scaling_pd = A[0] > 0 && minor2 > 0 && det3x3(A) > 0;  // Sylvester's criterion
  bool touched = false;
  if (!scaling_pd) {
    double S[9];
    for (int k = 0; k < 9; ++k) S[k] = A[k];
    project_psd<3>(S, 3);
    for (int k = 0; k < 9; ++k) S[k] -= A[k];
    double D[3][9];
    detail::scaling_basis(es, D);
    detail::add_scaling_block(D, S, dPdF);
    touched = true;
  }
  for (int m = 0; m < 6; ++m) {
    const double ev = es.pair_eigenvalues[m];
    if (ev >= 0) continue;
    double q[9];
    detail::pair_mode(es, m, q);
    detail::add_rank_one(-ev, q, dPdF);
    touched = true;
  }
  if (touched) detail::mirror_upper(dPdF);
}

}  // namespace dipc
