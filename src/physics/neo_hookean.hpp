// Compressible neo-Hookean material at a quadrature point (docs/design.md §1.2; the form
// used by the IPC paper and PolyFEM):
//   psi(F) = mu/2 (tr F^T F - 3) - mu ln J + lambda/2 (ln J)^2,   J = det F > 0,
// its first Piola-Kirchhoff stress P = d psi/dF, the exact 9x9 tangent dP/dF and the tangent
// projected to positive semi-definite through its analytic eigensystem. F and P are
// flattened row-major (k = 3i + j <-> F_ij); dPdF[9k + l] = dP_k/dF_l. All functions assume
// J > 0: inverted states are rejected by the callers before they get here.
#pragma once
#include <cmath>

#include "math/host_device.hpp"
#include "math/small_matrix.hpp"
#include "math/symmetric_eigen.hpp"
#include "physics/isotropic_eigensystem.hpp"

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
          double v = lambda * Finv[3 * j + i] * Finv[3 * l + k] - c * Finv[3 * j + k] * Finv[3 * l + i];
          if (r == s) v += mu;
          dPdF[9 * r + s] = dPdF[9 * s + r] = v;
        }
    }
}

// The analytic eigensystem of dP/dF (isotropic_eigensystem.hpp) for neo-Hookean: with
// c = lambda ln J - mu and psi_i = mu sigma_i + c / sigma_i,
//   A_ii = mu + (lambda (1 - ln J) + mu) / sigma_i^2,   A_ij = lambda / (sigma_i sigma_j),
//   flip  (psi_i - psi_j)/(sigma_i - sigma_j) = mu - c/(sigma_i sigma_j),
//   twist (psi_i + psi_j)/(sigma_i + sigma_j) = mu + c/(sigma_i sigma_j).
// Both closed forms avoid dividing by sigma_i - sigma_j. (At F = I the twists have eigenvalue
// 0: rotations.)
DIPC_HD void neo_hookean_eigensystem(const double F[9], double lambda, double mu, IsotropicEigensystem* es) {
  rotation_variant_svd(F, es->U, es->sigma, es->V);
  const double* s = es->sigma;
  const double log_J = log(s[0] * s[1] * s[2]);
  const double c = lambda * log_J - mu;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      es->scaling_hessian[3 * i + j] = i == j ? mu + (lambda * (1.0 - log_J) + mu) / (s[i] * s[i])
                                              : lambda / (s[i] * s[j]);
  int m = 0;
  for (int i = 0; i < 2; ++i)
    for (int j = i + 1; j < 3; ++j, m += 2) {
      const double r = c / (s[i] * s[j]);
      es->pair_eigenvalues[m] = mu - r;
      es->pair_eigenvalues[m + 1] = mu + r;
    }
}

// dP/dF rebuilt from all nine modes of the eigensystem, sum_k lambda_k q_k q_k^T, with the
// eigenvalues clamped at 0 when `clamp` is true. The reference form of the projection (and,
// unclamped, a check of the eigensystem against the exact tangent); the Newton hot path uses
// stress_derivative_psd<NeoHookean> (materials.hpp). Outer products are sign-invariant, so no eigenvector
// sign convention matters.
DIPC_HD void neo_hookean_stress_derivative_eigensystem(const double F[9], double lambda, double mu, bool clamp,
                                                       double dPdF[81]) {
  IsotropicEigensystem es;
  neo_hookean_eigensystem(F, lambda, mu, &es);
  double A[9];
  for (int k = 0; k < 9; ++k) A[k] = es.scaling_hessian[k];
  if (clamp) project_psd<3>(A, 3);  // same as clamping the scaling eigenvalues
  double D[3][9];
  detail::scaling_basis(es, D);
  for (int k = 0; k < 81; ++k) dPdF[k] = 0;
  detail::add_scaling_block(D, A, dPdF);
  for (int m = 0; m < 6; ++m) {
    const double ev = es.pair_eigenvalues[m];
    if (clamp && !(ev > 0)) continue;
    double q[9];
    detail::pair_mode(es, m, q);
    detail::add_rank_one(ev, q, dPdF);
  }
  detail::mirror_upper(dPdF);
}

// The material type that the hex8 element routines, the CPU loops and the CUDA kernel take
// as a template parameter (materials.hpp): psi, P, the exact dP/dF and its eigensystem (from
// which stress_derivative_psd<NeoHookean> projects it) at a quadrature point from the
// element's Lame parameters. Values of J <= 0 are outside its domain.
struct NeoHookean {
  DIPC_HD static double energy(const double F[9], double lambda, double mu) {
    return neo_hookean_energy(F, lambda, mu);
  }
  DIPC_HD static void stress(const double F[9], double lambda, double mu, double P[9]) {
    neo_hookean_stress(F, lambda, mu, P);
  }
  DIPC_HD static void stress_derivative(const double F[9], double lambda, double mu, double dPdF[81]) {
    neo_hookean_stress_derivative(F, lambda, mu, dPdF);
  }
  DIPC_HD static void eigensystem(const double F[9], double lambda, double mu, IsotropicEigensystem* es) {
    neo_hookean_eigensystem(F, lambda, mu, es);
  }
};

}  // namespace dipc
