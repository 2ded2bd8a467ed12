// Derivatives through a cross product n = a x b, shared by the quantities that depend on a
// normal or a cross product: the point-plane and line-line distances (n a triangle or
// edge-pair normal) and the edge-edge mollifier (c = |n|^2).
// First order: dn = da x b + a x db = -[b]_x da + [a]_x db.
// Second order: n_k = eps_kij a_i b_j is bilinear, so d^2 n_k / da_l db_m = eps_klm and
// sum_k (dF/dn_k) eps_klm = -([g_n]_x)_lm: the (a, b) block of the Hessian of F(n(a, b))
// gains -[g_n]_x and the (b, a) block its transpose, +[g_n]_x.
#pragma once
#include "math/host_device.hpp"
#include "math/vector3.hpp"

namespace dipc::contact {

// Writes dn/da = -[b]_x and dn/db = [a]_x into rows row0..row0+2 of the row-major matrix J
// (`cols` columns), at columns col_a..col_a+2 and col_b..col_b+2.
DIPC_HD void write_cross_product_jacobian(const double a[3], const double b[3], double* J, int cols, int row0,
                                          int col_a, int col_b) {
  double A[9], B[9];
  cross_matrix3(a, A);
  cross_matrix3(b, B);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      J[(row0 + i) * cols + col_a + j] = -B[3 * i + j];
      J[(row0 + i) * cols + col_b + j] = A[3 * i + j];
    }
}

// Adds the second-order term of F(n(a, b)), with g_n = dF/dn, to the n x n row-major
// Hessian H whose a and b dofs start at off_a and off_b.
DIPC_HD void add_cross_product_curvature(const double gn[3], double* H, int n, int off_a, int off_b) {
  double G[9];
  cross_matrix3(gn, G);
  for (int l = 0; l < 3; ++l)
    for (int m = 0; m < 3; ++m) {
      H[(off_a + l) * n + off_b + m] -= G[3 * l + m];
      H[(off_b + m) * n + off_a + l] -= G[3 * l + m];
    }
}

}  // namespace dipc::contact
