// Chain rule for contact distances written in a few intermediate vectors that are linear
// in the vertex positions (differences such as p - t0, or a cross product's Jacobian at a
// point): g_x = J^T g_y and H_x = J^T H_y J for y = J x, plus scattering of an elementary
// case's derivatives (over 2, 3 or 4 of the vertices) into the 12 stacked dofs of a
// point-triangle or edge-edge pair. Dense row-major arrays, sizes at most 12.
#pragma once
#include "math/host_device.hpp"

namespace dipc::contact {

// Largest number of dofs any contact point function differentiates (4 vertices x 3).
constexpr int kMaxContactDofs = 12;

// J (3 nv x 3 nd) = C (nv x nd) kron I3, for intermediate vectors y_a = sum_k C[a][k] x_k
// that are combinations of vertices x_k with scalar weights (e.g. p - t0: weights 1, -1).
DIPC_HD void vertex_combination_jacobian(const double* C, int nv, int nd, double* J) {
  const int cols = 3 * nd;
  for (int a = 0; a < nv; ++a)
    for (int k = 0; k < nd; ++k)
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) J[(3 * a + i) * cols + 3 * k + j] = (i == j) ? C[a * nd + k] : 0.0;
}

// g_x = J^T g_y, J is m x n.
DIPC_HD void pull_back_gradient(const double* J, int m, int n, const double* gy, double* gx) {
  for (int j = 0; j < n; ++j) {
    double s = 0.0;
    for (int k = 0; k < m; ++k) s += J[k * n + j] * gy[k];
    gx[j] = s;
  }
}

// H_x = J^T H_y J, J is m x n with m, n <= kMaxContactDofs.
DIPC_HD void pull_back_hessian(const double* J, int m, int n, const double* Hy, double* Hx) {
  double HJ[kMaxContactDofs * kMaxContactDofs];
  for (int k = 0; k < m; ++k)
    for (int j = 0; j < n; ++j) {
      double s = 0.0;
      for (int l = 0; l < m; ++l) s += Hy[k * m + l] * J[l * n + j];
      HJ[k * n + j] = s;
    }
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      double s = 0.0;
      for (int k = 0; k < m; ++k) s += J[k * n + i] * HJ[k * n + j];
      Hx[i * n + j] = s;
    }
}

// g (12) = the gradient g_local over the vertices ids[0..n) of the stacked pair, zero on
// the other vertices.
DIPC_HD void scatter_stacked_gradient(const double* g_local, const int* ids, int n, double g[12]) {
  for (int i = 0; i < 12; ++i) g[i] = 0.0;
  for (int a = 0; a < n; ++a)
    for (int i = 0; i < 3; ++i) g[3 * ids[a] + i] = g_local[3 * a + i];
}

// H (12 x 12) = the Hessian H_local over the vertices ids[0..n), zero elsewhere.
DIPC_HD void scatter_stacked_hessian(const double* H_local, const int* ids, int n, double H[144]) {
  for (int i = 0; i < 144; ++i) H[i] = 0.0;
  const int m = 3 * n;
  for (int a = 0; a < n; ++a)
    for (int b = 0; b < n; ++b)
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) H[(3 * ids[a] + i) * 12 + 3 * ids[b] + j] = H_local[(3 * a + i) * m + 3 * b + j];
}

}  // namespace dipc::contact
