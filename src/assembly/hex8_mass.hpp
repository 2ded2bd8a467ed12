// Mass matrices of the hex8 element with density rho, 2x2x2 Gauss. det J0 of a trilinear
// hex is at most quadratic in each reference coordinate, so the element volume (and the
// lumped masses' sum) is integrated exactly; N_a N_b det J0 is exact for parallelepipeds
// (constant det J0) and the usual reduced-order approximation otherwise. Host/device point
// functions; node reference coordinates X[3a + i].
#pragma once
#include "math/small_matrix.hpp"
#include "math/host_device.hpp"
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
// positive for valid elements and conserving total mass rho * volume.
DIPC_HD void hex8_lumped_mass(const double X[24], double rho, double m[8]) {
  for (int a = 0; a < 8; ++a) m[a] = 0;
  for (int q = 0; q < hex8::kQuadraturePoints; ++q) {
    double N[8];
    const double wdet = hex8_mass_point(X, rho, q, N);
    for (int a = 0; a < 8; ++a) m[a] += wdet * N[a];
  }
}

}  // namespace dipc
