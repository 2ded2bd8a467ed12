// Stable neo-Hookean material at a quadrature point (Smith, de Goes & Kim 2018, "Stable
// Neo-Hookean Flesh Simulation", ACM Trans. Graph. 37(2), eq. 14 and section 3.4):
//   psi(F) = mu'/2 (I_C - 3) + lambda'/2 (J - alpha)^2 - mu'/2 ln(I_C + 1),
//   I_C = tr F^T F,  J = det F,  alpha = 1 + 3 mu' / (4 lambda'),
// where alpha makes F = I stress-free. Unlike neo-Hookean's -mu ln J it has no singularity at
// J = 0 and stays finite (and smooth) for inverted F. Written here without the constant
// psi(I) (so that psi(I) = 0, like neo_hookean_energy) and without dividing by lambda':
//   psi(F) = mu'/2 (I_C - 3) - mu'/2 ln((I_C + 1)/4) + lambda'/2 (J - 1)^2 - 3 mu'/4 (J - 1).
// The element carries the Lame parameters (lambda, mu) of linear elasticity, from (E, nu) as
// for every material; the paper's reparametrisation (section 3.4)
//   mu' = 4/3 mu,   lambda' = lambda + 5/6 mu
// makes the linearisation at F = I that of linear elasticity with (lambda, mu), the same as
// neo-Hookean's (lambda' > 0 for every nu in (-1, 0.5)). Flattening conventions as in
// neo_hookean.hpp.
#pragma once
#include <cmath>

#include "math/host_device.hpp"
#include "math/small_matrix.hpp"
#include "physics/isotropic_eigensystem.hpp"

namespace dipc {

// The paper's (lambda', mu') from the linear-elastic Lame parameters.
DIPC_HD void stable_neo_hookean_parameters(double lambda, double mu, double* lambda_s, double* mu_s) {
  *mu_s = 4.0 / 3.0 * mu;
  *lambda_s = lambda + 5.0 / 6.0 * mu;
}

// Cofactor matrix cof F = dJ/dF = J F^{-T}, a polynomial in F (defined for any F).
DIPC_HD void cofactor3x3(const double F[9], double C[9]) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      const int i1 = (i + 1) % 3, i2 = (i + 2) % 3, j1 = (j + 1) % 3, j2 = (j + 2) % 3;
      C[3 * i + j] = F[3 * i1 + j1] * F[3 * i2 + j2] - F[3 * i1 + j2] * F[3 * i2 + j1];
    }
}

DIPC_HD double stable_neo_hookean_energy(const double F[9], double lambda, double mu) {
  double ls, ms;
  stable_neo_hookean_parameters(lambda, mu, &ls, &ms);
  const double Ic = double_contraction3x3(F, F), Jm1 = det3x3(F) - 1.0;
  return 0.5 * ms * (Ic - 3.0) - 0.5 * ms * log(0.25 * (Ic + 1.0)) + 0.5 * ls * Jm1 * Jm1 - 0.75 * ms * Jm1;
}

// P = mu' (1 - 1/(I_C + 1)) F + kappa cof F,   kappa = dpsi/dJ = lambda' (J - 1) - 3 mu'/4.
DIPC_HD void stable_neo_hookean_stress(const double F[9], double lambda, double mu, double P[9]) {
  double ls, ms, cof[9];
  stable_neo_hookean_parameters(lambda, mu, &ls, &ms);
  cofactor3x3(F, cof);
  const double Ic = double_contraction3x3(F, F);
  const double a = ms * (1.0 - 1.0 / (Ic + 1.0)), kappa = ls * (det3x3(F) - 1.0) - 0.75 * ms;
  for (int k = 0; k < 9; ++k) P[k] = a * F[k] + kappa * cof[k];
}

// dP/dF = mu'(1 - 1/(I_C+1)) I + 2 mu'/(I_C+1)^2 vec F vec F^T + lambda' vec cof F vec cof F^T
//         + kappa d2J/dF2,
// with d(cof F)_ij/dF_kl = eps_ikn eps_jlq F_nq (the derivative of
// cof F_ij = 1/2 eps_imn eps_jpq F_mp F_nq), zero when i = k or j = l.
DIPC_HD void stable_neo_hookean_stress_derivative(const double F[9], double lambda, double mu, double dPdF[81]) {
  double ls, ms, cof[9];
  stable_neo_hookean_parameters(lambda, mu, &ls, &ms);
  cofactor3x3(F, cof);
  const double Ic = double_contraction3x3(F, F);
  const double a = ms * (1.0 - 1.0 / (Ic + 1.0)), b = 2.0 * ms / ((Ic + 1.0) * (Ic + 1.0));
  const double kappa = ls * (det3x3(F) - 1.0) - 0.75 * ms;
  for (int r = 0; r < 9; ++r)
    for (int s = r; s < 9; ++s) {
      const int i = r / 3, j = r % 3, k = s / 3, l = s % 3;
      double v = b * F[r] * F[s] + ls * cof[r] * cof[s];
      if (r == s) v += a;
      if (i != k && j != l) {
        // eps_ikn for the third index n: +1 when (i, k) is cyclic (k = i + 1 mod 3).
        const double e_ik = (k - i + 3) % 3 == 1 ? 1.0 : -1.0, e_jl = (l - j + 3) % 3 == 1 ? 1.0 : -1.0;
        v += kappa * e_ik * e_jl * F[3 * (3 - i - k) + (3 - j - l)];
      }
      dPdF[9 * r + s] = dPdF[9 * s + r] = v;
    }
}

// The analytic eigensystem of dP/dF (isotropic_eigensystem.hpp; the paper's section 4.3 gives
// the same modes). In signed singular values, I_C = sum sigma_i^2, J = sigma_0 sigma_1 sigma_2,
// Pi_i = J / sigma_i = sigma_j sigma_k, r = mu'/(I_C + 1) and kappa as above:
//   psi_i = (mu' - r) sigma_i + kappa Pi_i,
//   A_ii = mu' - r + 2 r sigma_i^2/(I_C + 1) + lambda' Pi_i^2,
//   A_ij = 2 r sigma_i sigma_j/(I_C + 1) + lambda' Pi_i Pi_j + kappa sigma_k,
//   flip  (psi_i - psi_j)/(sigma_i - sigma_j) = mu' - r - kappa sigma_k,
//   twist (psi_i + psi_j)/(sigma_i + sigma_j) = mu' - r + kappa sigma_k.
// No division by a singular value: valid for inverted F too (sigma_2 <= 0).
DIPC_HD void stable_neo_hookean_eigensystem(const double F[9], double lambda, double mu, IsotropicEigensystem* es) {
  double ls, ms;
  stable_neo_hookean_parameters(lambda, mu, &ls, &ms);
  rotation_variant_svd(F, es->U, es->sigma, es->V);
  const double* s = es->sigma;
  const double Ic = s[0] * s[0] + s[1] * s[1] + s[2] * s[2];
  const double r = ms / (Ic + 1.0), kappa = ls * (s[0] * s[1] * s[2] - 1.0) - 0.75 * ms;
  const double Pi[3] = {s[1] * s[2], s[0] * s[2], s[0] * s[1]};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      double v = 2.0 * r * s[i] * s[j] / (Ic + 1.0) + ls * Pi[i] * Pi[j];
      v += i == j ? ms - r : kappa * s[3 - i - j];
      es->scaling_hessian[3 * i + j] = v;
    }
  int m = 0;
  for (int i = 0; i < 2; ++i)
    for (int j = i + 1; j < 3; ++j, m += 2) {
      const double t = kappa * s[3 - i - j];
      es->pair_eigenvalues[m] = ms - r - t;
      es->pair_eigenvalues[m + 1] = ms - r + t;
    }
}

// The material type (materials.hpp). Its point functions are finite for any F of rank >= 2,
// inverted or not; the hex8 element still refuses det F <= 0 (hex8_elasticity.hpp), because
// dipc keeps every element uninverted (line-search filter), whatever the material.
struct StableNeoHookean {
  DIPC_HD static double energy(const double F[9], double lambda, double mu) {
    return stable_neo_hookean_energy(F, lambda, mu);
  }
  DIPC_HD static void stress(const double F[9], double lambda, double mu, double P[9]) {
    stable_neo_hookean_stress(F, lambda, mu, P);
  }
  DIPC_HD static void stress_derivative(const double F[9], double lambda, double mu, double dPdF[81]) {
    stable_neo_hookean_stress_derivative(F, lambda, mu, dPdF);
  }
  DIPC_HD static void eigensystem(const double F[9], double lambda, double mu, IsotropicEigensystem* es) {
    stable_neo_hookean_eigensystem(F, lambda, mu, es);
  }
};

}  // namespace dipc
