// The trilinear hexahedron (hex8) on the reference cube [-1,1]^3: shape functions, their
// derivatives, corner coordinates and the 2x2x2 Gauss rule. Pure host/device functions,
// shared by mesh validation, the CPU element loops and the CUDA kernels.
#pragma once
#include "math/host_device.hpp"
#include "math/small_matrix.hpp"

namespace dipc::hex8 {

constexpr int kNodes = 8;
constexpr int kQuadraturePoints = 8;

// Reference coordinate signs of node a (Gmsh/VTK ordering, see hex_mesh.hpp).
DIPC_HD double corner_xi(int a) { return (a == 1 || a == 2 || a == 5 || a == 6) ? 1.0 : -1.0; }
DIPC_HD double corner_eta(int a) { return (a == 2 || a == 3 || a == 6 || a == 7) ? 1.0 : -1.0; }
DIPC_HD double corner_zeta(int a) { return a >= 4 ? 1.0 : -1.0; }

// N_a(ξ,η,ζ) = (1 + ξ_a ξ)(1 + η_a η)(1 + ζ_a ζ) / 8
DIPC_HD void shape(double xi, double eta, double zeta, double N[8]) {
  for (int a = 0; a < 8; ++a)
    N[a] = 0.125 * (1 + corner_xi(a) * xi) * (1 + corner_eta(a) * eta) * (1 + corner_zeta(a) * zeta);
}

// dN_a/dξ_k, stored dN[3*a + k].
DIPC_HD void shape_gradient(double xi, double eta, double zeta, double dN[24]) {
  for (int a = 0; a < 8; ++a) {
    const double sx = corner_xi(a), sy = corner_eta(a), sz = corner_zeta(a);
    dN[3 * a + 0] = 0.125 * sx * (1 + sy * eta) * (1 + sz * zeta);
    dN[3 * a + 1] = 0.125 * sy * (1 + sx * xi) * (1 + sz * zeta);
    dN[3 * a + 2] = 0.125 * sz * (1 + sx * xi) * (1 + sy * eta);
  }
}

// 2x2x2 Gauss-Legendre: points ±1/√3, all weights 1 (they sum to the cube volume 8).
DIPC_HD void gauss_point(int q, double& xi, double& eta, double& zeta) {
  const double g = 0.57735026918962576451;  // 1/sqrt(3)
  xi = (q & 1) ? g : -g;
  eta = (q & 2) ? g : -g;
  zeta = (q & 4) ? g : -g;
}
constexpr double kGaussWeight = 1.0;

// Jacobian J_ij = dx_i/dξ_j of the map from the reference cube to the element with node
// coordinates X[3*a + i], at the point whose shape gradients are dN.
DIPC_HD void jacobian(const double X[24], const double dN[24], double J[9]) {
  for (int i = 0; i < 9; ++i) J[i] = 0;
  for (int a = 0; a < 8; ++a)
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) J[3 * i + j] += X[3 * a + i] * dN[3 * a + j];
}

// Smallest det J over the 8 corners and the 8 Gauss points: the element is valid (not
// inverted, not degenerate) iff this is > 0. Corners catch inversions that the Gauss
// points miss on strongly distorted elements.
DIPC_HD double min_jacobian_determinant(const double X[24]) {
  double dN[24], J[9];
  double m = 1e300;
  for (int p = 0; p < 16; ++p) {
    double xi, eta, zeta;
    if (p < 8) {
      xi = corner_xi(p), eta = corner_eta(p), zeta = corner_zeta(p);
    } else {
      gauss_point(p - 8, xi, eta, zeta);
    }
    shape_gradient(xi, eta, zeta, dN);
    jacobian(X, dN, J);
    const double d = det3x3(J);
    m = d < m ? d : m;
  }
  return m;
}

}  // namespace dipc::hex8
