// Element energy, gradient and Hessian of the hyperelastic hex8 (trilinear, 2x2x2 Gauss) for
// any material type of materials.hpp, and its volume ratio check. Host/device point functions
// on plain arrays: node reference coordinates X[3a + i] and current positions x[3a + i]
// (Gmsh/VTK node order, see mesh/hex_mesh.hpp); gradients have 24 entries (element dof
// 3a + i), Hessians are 24x24 row-major.
#pragma once
#include "math/host_device.hpp"
#include "math/small_matrix.hpp"
#include "mesh/hex8_reference.hpp"
#include "physics/materials.hpp"

namespace dipc {

// Geometry of Gauss point q: the reference shape gradients G_a = dN_a/dX = J0^{-T} dN_a/dxi
// (G[3a + j]), the deformation gradient F = sum_a x_a (x) G_a, and the returned quadrature
// weight w_q |det J0_q|. Shared by the CPU element loop and the CUDA element kernel.
DIPC_HD double hex8_quadrature_point(const double X[24], const double x[24], int q, double G[24], double F[9]) {
  double xi, eta, zeta, dN[24], J0[9], J0inv[9];
  hex8::gauss_point(q, xi, eta, zeta);
  hex8::shape_gradient(xi, eta, zeta, dN);
  hex8::jacobian(X, dN, J0);
  const double det_J0 = inverse3x3(J0, J0inv);
  for (int a = 0; a < 8; ++a)
    for (int j = 0; j < 3; ++j)
      G[3 * a + j] = dN[3 * a] * J0inv[j] + dN[3 * a + 1] * J0inv[3 + j] + dN[3 * a + 2] * J0inv[6 + j];
  for (int k = 0; k < 9; ++k) F[k] = 0;
  for (int a = 0; a < 8; ++a)
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) F[3 * i + j] += x[3 * a + i] * G[3 * a + j];
  return hex8::kGaussWeight * (det_J0 < 0 ? -det_J0 : det_J0);
}

namespace detail {

// The element sums of the total-Lagrangian discretisation (e.g. Bonet & Wood, Nonlinear
// Continuum Mechanics for Finite Element Analysis, chapter "Discretization and solution"):
// with F = sum_a x_a (x) G_a, dF_ij/dx_ak = d_ik G_aj, so a quadrature point with weighted
// stress wP and weighted tangent wC adds
//   g_ak += sum_j wP_kj G_aj,     H_(ak)(bl) += sum_jm G_aj wC_(kj)(lm) G_bm   (B^T C B).

DIPC_HD void add_point_gradient(const double G[24], const double wP[9], double gradient[24]) {
  for (int a = 0; a < 8; ++a)
    for (int k = 0; k < 3; ++k)
      gradient[3 * a + k] += wP[3 * k] * G[3 * a] + wP[3 * k + 1] * G[3 * a + 1] + wP[3 * k + 2] * G[3 * a + 2];
}

// Accumulated in component-major order Hc[(8k + a)][(8l + b)] so that the innermost loop
// runs over 8 contiguous nodes b (vectorisable); finish_hessian permutes once at the end.
DIPC_HD void add_point_hessian(const double G[24], double wdet, const double C[81], double Hc[576]) {
  double Gt[24];
  for (int a = 0; a < 8; ++a)
    for (int j = 0; j < 3; ++j) Gt[8 * j + a] = G[3 * a + j];
  for (int a = 0; a < 8; ++a) {
    // T_k,(lm) = w|J0| sum_j G_aj C_(kj),(lm): contract the left index once per node a.
    double T[27];
    for (int k = 0; k < 3; ++k)
      for (int lm = 0; lm < 9; ++lm)
        T[9 * k + lm] = wdet * (G[3 * a] * C[9 * (3 * k) + lm] + G[3 * a + 1] * C[9 * (3 * k + 1) + lm] +
                                G[3 * a + 2] * C[9 * (3 * k + 2) + lm]);
    for (int k = 0; k < 3; ++k)
      for (int l = 0; l < 3; ++l) {
        double* row = Hc + 24 * (8 * k + a) + 8 * l;
        const double t0 = T[9 * k + 3 * l], t1 = T[9 * k + 3 * l + 1], t2 = T[9 * k + 3 * l + 2];
        for (int b = 0; b < 8; ++b) row[b] += t0 * Gt[b] + t1 * Gt[8 + b] + t2 * Gt[16 + b];
      }
  }
}

// Back to element dof order 3a + k, symmetrised: (Hc + Hc^T)/2 equals Hc up to rounding
// (every added tangent is symmetric) and makes the output exactly symmetric.
DIPC_HD void finish_hessian(const double Hc[576], double hessian[576]) {
  for (int a = 0; a < 8; ++a)
    for (int k = 0; k < 3; ++k)
      for (int b = 0; b < 8; ++b)
        for (int l = 0; l < 3; ++l)
          hessian[24 * (3 * a + k) + 3 * b + l] = 0.5 *
                                                  (Hc[24 * (8 * k + a) + 8 * l + b] + Hc[24 * (8 * l + b) + 8 * k + a]);
}

// Psi_e = sum_q w_q |det J0_q| psi(F_q) with psi the Material's energy at each of the 2x2x2
// Gauss points. `Project` selects the PSD-projected dP/dF (Newton) or the exact one
// (derivative tests). det F <= 0 is refused for every material, also for those whose psi is
// finite there (stable neo-Hookean): dipc keeps elements uninverted.
template <class Material, bool Project>
DIPC_HD bool hex8_hyperelastic(const double X[24], const double x[24], double lambda, double mu, double* energy,
                               double* gradient, double* hessian) {
  double e = 0;
  if (gradient)
    for (int k = 0; k < 24; ++k) gradient[k] = 0;
  double Hc[576];
  if (hessian)
    for (int k = 0; k < 576; ++k) Hc[k] = 0;
  for (int q = 0; q < hex8::kQuadraturePoints; ++q) {
    double G[24], F[9];
    const double wdet = hex8_quadrature_point(X, x, q, G, F);
    if (!(det3x3(F) > 0)) return false;
    if (energy) e += wdet * Material::energy(F, lambda, mu);
    if (gradient) {
      double P[9];
      Material::stress(F, lambda, mu, P);
      for (int k = 0; k < 9; ++k) P[k] *= wdet;
      add_point_gradient(G, P, gradient);
    }
    if (hessian) {
      double C[81];
      if (Project)
        stress_derivative_psd<Material>(F, lambda, mu, C);
      else
        Material::stress_derivative(F, lambda, mu, C);
      add_point_hessian(G, wdet, C, Hc);
    }
  }
  if (hessian) finish_hessian(Hc, hessian);
  if (energy) *energy = e;
  return true;
}

}  // namespace detail

// Energy, gradient (24 or nullptr) and PSD-projected Hessian (576 or nullptr) of one element
// of the given material; `energy` may be nullptr too. Returns false, outputs unspecified, when
// det F <= 0 at a quadrature point.
template <class Material>
DIPC_HD bool hex8_element(const double X[24], const double x[24], double lambda, double mu, double* energy,
                          double* gradient, double* hessian) {
  return detail::hex8_hyperelastic<Material, true>(X, x, lambda, mu, energy, gradient, hessian);
}

// Same with the exact (unprojected, possibly indefinite) Hessian: the true second
// derivative, for finite-difference tests and for solvers that do their own safeguarding.
template <class Material>
DIPC_HD bool hex8_element_exact_hessian(const double X[24], const double x[24], double lambda, double mu,
                                        double* energy, double* gradient, double* hessian) {
  return detail::hex8_hyperelastic<Material, false>(X, x, lambda, mu, energy, gradient, hessian);
}

// The neo-Hookean element (the default material).
DIPC_HD bool hex8_neo_hookean(const double X[24], const double x[24], double lambda, double mu, double* energy,
                              double* gradient, double* hessian) {
  return hex8_element<NeoHookean>(X, x, lambda, mu, energy, gradient, hessian);
}

DIPC_HD bool hex8_neo_hookean_exact_hessian(const double X[24], const double x[24], double lambda, double mu,
                                            double* energy, double* gradient, double* hessian) {
  return hex8_element_exact_hessian<NeoHookean>(X, x, lambda, mu, energy, gradient, hessian);
}

// min det F over the 8 Gauss points and the 8 corners, det F = det(dx/dxi) / det(dX/dxi):
// the local volume ratio. <= 0 means the trial state inverts the element somewhere; corners
// catch inversions that the Gauss points miss on distorted elements.
DIPC_HD double hex8_min_volume_ratio(const double X[24], const double x[24]) {
  double m = 1e300;
  for (int p = 0; p < 16; ++p) {
    double xi, eta, zeta, dN[24], J0[9], J[9];
    if (p < 8) {
      xi = hex8::corner_xi(p), eta = hex8::corner_eta(p), zeta = hex8::corner_zeta(p);
    } else {
      hex8::gauss_point(p - 8, xi, eta, zeta);
    }
    hex8::shape_gradient(xi, eta, zeta, dN);
    hex8::jacobian(X, dN, J0);
    hex8::jacobian(x, dN, J);
    const double ratio = det3x3(J) / det3x3(J0);
    m = ratio < m ? ratio : m;
  }
  return m;
}

}  // namespace dipc
