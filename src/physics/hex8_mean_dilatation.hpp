// The mean-dilatation hex8: neo-Hookean with its volumetric term evaluated on the element's
// mean volume ratio, a locking-free element for nearly incompressible materials.
//
// The 2x2x2-point hex8 imposes ln J ~ 0 at 8 points per element while it has about 3 dofs per
// element: as nu -> 0.5 the mesh locks (too stiff, wrong answer) and the Hessian is dominated
// by lambda on almost every mode, which is what makes CG + AMG slow. The mean-dilatation
// element (Nagtegaal, Parks & Rice 1974; Simo, Taylor & Pister 1985, CMAME 51, "Variational
// and projection methods for the volume constraint in finite deformation elasto-plasticity";
// the Q1/P0 element with the pressure condensed out) keeps the deviatoric part at the Gauss
// points and constrains one volume per element:
//   Psi_e = sum_q w_q |J0_q| psi_dev(F_q) + V lambda/2 (ln Jbar)^2,
//   psi_dev(F) = mu/2 (tr F^T F - 3) - mu ln J,     Jbar = v / V,
//   V = sum_q w_q |J0_q| (reference volume), v = sum_q w_q |J0_q| det F_q (current volume; the
//   2x2x2 rule integrates det(dx/dxi) of a trilinear map exactly).
// With f(v) = V lambda/2 (ln(v/V))^2: f'(v) = lambda ln Jbar / Jbar =: p and
// f''(v) = lambda (1 - ln Jbar) / (V Jbar^2), and since dv/dF_q = w|J0| J F^{-T},
//   g = sum_q w|J0| B_q^T [P_dev(F_q) + p J_q F_q^{-T}],
//   H = sum_q w|J0| B_q^T [dP_dev/dF + p d2J/dF2](F_q) B_q + f''(v) b b^T,   b = dv/dx.
// The energy equals the standard element's for a homogeneous deformation, and for lambda = 0.
// The Newton Hessian projects each point's tangent dP_dev/dF + p d2J/dF2 (the tangent of the
// isotropic energy psi_dev + p J, p frozen) through its analytic eigensystem, and drops the
// rank-one term when f'' < 0 (Jbar > e): a sum of PSD parts, as the standard element does.
#pragma once
#include "math/host_device.hpp"
#include "math/small_matrix.hpp"
#include "physics/hex8_elasticity.hpp"
#include "physics/materials.hpp"
#include "physics/neo_hookean.hpp"

namespace dipc {

// Eigensystem of the tangent of psi_dev(F) + p det F (Smith, de Goes & Kim 2019, as in
// neo_hookean_eigensystem). In singular values, psi_dev + p J has the Hessian
//   A_ii = mu + mu / sigma_i^2,   A_ij = p sigma_k   (k the third index),
// and with psi_i = mu sigma_i - mu / sigma_i + p sigma_j sigma_k the pair modes have
//   flip  (psi_i - psi_j)/(sigma_i - sigma_j) = mu + mu/(sigma_i sigma_j) - p sigma_k,
//   twist (psi_i + psi_j)/(sigma_i + sigma_j) = mu - mu/(sigma_i sigma_j) + p sigma_k.
DIPC_HD void mean_dilatation_eigensystem(const double F[9], double mu, double p, IsotropicEigensystem* es) {
  rotation_variant_svd(F, es->U, es->sigma, es->V);
  const double* s = es->sigma;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) es->scaling_hessian[3 * i + j] = i == j ? mu + mu / (s[i] * s[i]) : p * s[3 - i - j];
  int m = 0;
  for (int i = 0; i < 2; ++i)
    for (int j = i + 1; j < 3; ++j, m += 2) {
      const double r = mu / (s[i] * s[j]), t = p * s[3 - i - j];
      es->pair_eigenvalues[m] = mu + r - t;
      es->pair_eigenvalues[m + 1] = mu - r + t;
    }
}

// Exact tangent of psi_dev + p J: dP_dev/dF (neo-Hookean with lambda = 0) plus
// p d2J/dF_ij dF_kl = p J (F^{-1}_ji F^{-1}_lk - F^{-1}_jk F^{-1}_li) (J F^{-T} differentiated).
DIPC_HD void mean_dilatation_point_tangent(const double F[9], double mu, double p, double dPdF[81]) {
  neo_hookean_stress_derivative(F, 0.0, mu, dPdF);
  double Finv[9];
  const double pJ = p * inverse3x3(F, Finv);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k)
        for (int l = 0; l < 3; ++l)
          dPdF[9 * (3 * i + j) + 3 * k + l] += pJ *
                                               (Finv[3 * j + i] * Finv[3 * l + k] - Finv[3 * j + k] * Finv[3 * l + i]);
}

namespace detail {

// With `volume_gradient` (24) and `volume_curvature` given, the rank-one term f'' b b^T is left
// out of `hessian` and returned as b = dv/dx and f''(v) (clamped at 0 when projecting), so a
// solver can keep the stiff volumetric part apart (a mixed u-p linear solve).
template <bool Project>
DIPC_HD bool hex8_mean_dilatation(const double X[24], const double x[24], double lambda, double mu, double* energy,
                                  double* gradient, double* hessian, double* volume_gradient = nullptr,
                                  double* volume_curvature = nullptr) {
  // First pass: reference and current volumes (every point's det F must be positive).
  double G[8][24], F[8][9], wdet[8], J[8];
  double V = 0, v = 0;
  for (int q = 0; q < hex8::kQuadraturePoints; ++q) {
    wdet[q] = hex8_quadrature_point(X, x, q, G[q], F[q]);
    J[q] = det3x3(F[q]);
    if (!(J[q] > 0)) return false;
    V += wdet[q];
    v += wdet[q] * J[q];
  }
  const double Jbar = v / V, log_Jbar = log(Jbar);
  const double p = lambda * log_Jbar / Jbar;
  if (energy) {
    double e = 0.5 * V * lambda * log_Jbar * log_Jbar;
    for (int q = 0; q < hex8::kQuadraturePoints; ++q) e += wdet[q] * neo_hookean_energy(F[q], 0.0, mu);
    *energy = e;
  }
  if (gradient) {
    for (int k = 0; k < 24; ++k) gradient[k] = 0;
    for (int q = 0; q < hex8::kQuadraturePoints; ++q) {
      double P[9], FinvT[9];
      neo_hookean_stress(F[q], 0.0, mu, P);
      inverse_transpose3x3(F[q], FinvT);
      for (int k = 0; k < 9; ++k) P[k] = wdet[q] * (P[k] + p * J[q] * FinvT[k]);
      add_point_gradient(G[q], P, gradient);
    }
  }
  if (hessian) {
    double Hc[576], b[24];
    for (int k = 0; k < 576; ++k) Hc[k] = 0;
    for (int k = 0; k < 24; ++k) b[k] = 0;
    for (int q = 0; q < hex8::kQuadraturePoints; ++q) {
      double C[81];
      mean_dilatation_point_tangent(F[q], mu, p, C);
      if (Project) {
        IsotropicEigensystem es;
        mean_dilatation_eigensystem(F[q], mu, p, &es);
        add_psd_correction(es, C);
      }
      add_point_hessian(G[q], wdet[q], C, Hc);
      double dv[9];  // dv/dF_q = w|J0| J F^{-T}
      inverse_transpose3x3(F[q], dv);
      for (int k = 0; k < 9; ++k) dv[k] *= wdet[q] * J[q];
      add_point_gradient(G[q], dv, b);
    }
    double f2 = lambda * (1.0 - log_Jbar) / (V * Jbar * Jbar);
    if (Project && f2 < 0) f2 = 0;
    if (volume_gradient) {
      for (int k = 0; k < 24; ++k) volume_gradient[k] = b[k];
      *volume_curvature = f2;
    } else {
      // Hc is component-major: entry (8k + a, 8l + c) for dofs (3a + k, 3c + l).
      for (int a = 0; a < 8; ++a)
        for (int k = 0; k < 3; ++k)
          for (int c = 0; c < 8; ++c)
            for (int l = 0; l < 3; ++l) Hc[24 * (8 * k + a) + 8 * l + c] += f2 * b[3 * a + k] * b[3 * c + l];
    }
    finish_hessian(Hc, hessian);
  }
  return true;
}

}  // namespace detail

// Energy, gradient (24 or nullptr) and PSD-projected Hessian (576 or nullptr) of one
// mean-dilatation element; false, outputs unspecified, when det F <= 0 at a quadrature point.
DIPC_HD bool hex8_mean_dilatation(const double X[24], const double x[24], double lambda, double mu, double* energy,
                                  double* gradient, double* hessian) {
  return detail::hex8_mean_dilatation<true>(X, x, lambda, mu, energy, gradient, hessian);
}

// Same with the exact (unprojected) Hessian, for finite-difference tests.
DIPC_HD bool hex8_mean_dilatation_exact_hessian(const double X[24], const double x[24], double lambda, double mu,
                                                double* energy, double* gradient, double* hessian) {
  return detail::hex8_mean_dilatation<false>(X, x, lambda, mu, energy, gradient, hessian);
}

// How an element integrates its volumetric term lambda/2 (ln J)^2: at the 8 Gauss points (the
// standard element, PolyFEM's and the IPC paper's) or on the element's mean volume ratio.
// Chosen per material (scene key materials[].volumetric).
enum class VolumetricTerm : unsigned char { gauss_points = 0, mean_dilatation = 1 };

// The element of either kind and any material (materials.hpp): energy, gradient and
// PSD-projected Hessian as above. The mean-dilatation element is the neo-Hookean one: with
// `term` mean_dilatation, `model` must be neo_hookean (ElementData and the scene parser refuse
// other materials with it).
template <class Material>
DIPC_HD bool hex8_elastic(VolumetricTerm term, const double X[24], const double x[24], double lambda, double mu,
                          double* energy, double* gradient, double* hessian) {
  if (term == VolumetricTerm::mean_dilatation) return hex8_mean_dilatation(X, x, lambda, mu, energy, gradient, hessian);
  return hex8_element<Material>(X, x, lambda, mu, energy, gradient, hessian);
}

// The same with the material chosen at run time.
DIPC_HD bool hex8_elastic(VolumetricTerm term, MaterialModel model, const double X[24], const double x[24],
                          double lambda, double mu, double* energy, double* gradient, double* hessian) {
  return visit_material(model, [&](auto material) {
    return hex8_elastic<decltype(material)>(term, X, x, lambda, mu, energy, gradient, hessian);
  });
}

}  // namespace dipc
