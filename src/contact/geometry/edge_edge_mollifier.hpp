// IPC's mollifier for nearly parallel edges (Li et al. 2020, "Incremental Potential
// Contact", ACM TOG 39(4), §4.3 and supplement): the edge-edge barrier is multiplied by
//   m(c) = -c^2 / eps_x^2 + 2 c / eps_x  for c < eps_x,  1 otherwise,
//   c = |(ea1 - ea0) x (eb1 - eb0)|^2,  eps_x = 1e-3 |ea0_rest - ea1_rest|^2 |eb0_rest - eb1_rest|^2,
// so the barrier and its gradient go to zero smoothly (m is C1 at eps_x: m(eps_x) = 1,
// m'(eps_x) = 0) as the edges become parallel, where the edge-edge distance loses its
// derivatives (and its contact is carried by the point-triangle pairs anyway).
// Derivatives w.r.t. the stacked dofs [ea0, ea1, eb0, eb1]:
//   grad m = m'(c) grad c,  hess m = m''(c) grad c grad c^T + m'(c) hess c,
// with c = |n|^2, n = u x v: dc/dn = 2 n, d^2c/dn^2 = 2 I, pulled back through the cross
// product (cross_product_derivatives.hpp) and u = ea1 - ea0, v = eb1 - eb0.
#pragma once
#include "contact/geometry/chain_rule.hpp"
#include "contact/geometry/cross_product_derivatives.hpp"
#include "math/host_device.hpp"
#include "math/vector3.hpp"

namespace dipc::contact {

// eps_x from the rest positions of the two edges.
DIPC_HD double edge_edge_mollifier_threshold(const double ea0_rest[3], const double ea1_rest[3],
                                             const double eb0_rest[3], const double eb1_rest[3]) {
  double u[3], v[3];
  subtract3(ea1_rest, ea0_rest, u);
  subtract3(eb1_rest, eb0_rest, v);
  return 1e-3 * squared_norm3(u) * squared_norm3(v);
}

// m(c) and its first two derivatives in c.
DIPC_HD double mollifier(double c, double eps_x) {
  if (c >= eps_x) return 1.0;
  const double x = c / eps_x;
  return (2.0 - x) * x;
}

DIPC_HD double mollifier_first_derivative(double c, double eps_x) {
  if (c >= eps_x) return 0.0;
  return 2.0 / eps_x * (1.0 - c / eps_x);
}

DIPC_HD double mollifier_second_derivative(double c, double eps_x) {
  if (c >= eps_x) return 0.0;
  return -2.0 / (eps_x * eps_x);
}

namespace detail {
// J (6 x 12) of u = ea1 - ea0, v = eb1 - eb0 w.r.t. [ea0, ea1, eb0, eb1].
DIPC_HD void edge_directions_jacobian(double J[6 * 12]) {
  const double C[] = {-1.0, 1.0, 0.0,  0.0,  //
                      0.0,  0.0, -1.0, 1.0};
  vertex_combination_jacobian(C, 2, 4, J);
}
}  // namespace detail

// c = |(ea1 - ea0) x (eb1 - eb0)|^2 and its derivatives w.r.t. the 12 stacked dofs.
DIPC_HD double edge_edge_cross_squared_norm(const double ea0[3], const double ea1[3], const double eb0[3],
                                            const double eb1[3]) {
  double u[3], v[3], n[3];
  subtract3(ea1, ea0, u);
  subtract3(eb1, eb0, v);
  cross3(u, v, n);
  return squared_norm3(n);
}

DIPC_HD void edge_edge_cross_squared_norm_gradient(const double ea0[3], const double ea1[3], const double eb0[3],
                                                   const double eb1[3], double g[12]) {
  double u[3], v[3], n[3], gu[3], gv[3], J[6 * 12];
  subtract3(ea1, ea0, u);
  subtract3(eb1, eb0, v);
  cross3(u, v, n);
  // dc/du = v x (2 n), dc/dv = (2 n) x u (transposes of the cross-product Jacobians).
  cross3(v, n, gu);
  cross3(n, u, gv);
  double guv[6];
  for (int i = 0; i < 3; ++i) {
    guv[i] = 2.0 * gu[i];
    guv[3 + i] = 2.0 * gv[i];
  }
  detail::edge_directions_jacobian(J);
  pull_back_gradient(J, 6, 12, guv, g);
}

DIPC_HD void edge_edge_cross_squared_norm_hessian(const double ea0[3], const double ea1[3], const double eb0[3],
                                                  const double eb1[3], double H[144]) {
  double u[3], v[3], n[3];
  subtract3(ea1, ea0, u);
  subtract3(eb1, eb0, v);
  cross3(u, v, n);
  double Jn[3 * 6];
  write_cross_product_jacobian(u, v, Jn, 6, 0, 0, 3);
  const double Hn[9] = {2.0, 0.0, 0.0, 0.0, 2.0, 0.0, 0.0, 0.0, 2.0};
  double Huv[36];
  pull_back_hessian(Jn, 3, 6, Hn, Huv);
  const double gn[3] = {2.0 * n[0], 2.0 * n[1], 2.0 * n[2]};
  add_cross_product_curvature(gn, Huv, 6, 0, 3);
  double J[6 * 12];
  detail::edge_directions_jacobian(J);
  pull_back_hessian(J, 6, 12, Huv, H);
}

// m and its derivatives w.r.t. the 12 stacked dofs; eps_x from
// edge_edge_mollifier_threshold on the rest positions.
DIPC_HD double edge_edge_mollifier(const double ea0[3], const double ea1[3], const double eb0[3], const double eb1[3],
                                   double eps_x) {
  return mollifier(edge_edge_cross_squared_norm(ea0, ea1, eb0, eb1), eps_x);
}

DIPC_HD void edge_edge_mollifier_gradient(const double ea0[3], const double ea1[3], const double eb0[3],
                                          const double eb1[3], double eps_x, double g[12]) {
  const double c = edge_edge_cross_squared_norm(ea0, ea1, eb0, eb1);
  const double dm = mollifier_first_derivative(c, eps_x);
  edge_edge_cross_squared_norm_gradient(ea0, ea1, eb0, eb1, g);
  for (int i = 0; i < 12; ++i) g[i] *= dm;
}

DIPC_HD void edge_edge_mollifier_hessian(const double ea0[3], const double ea1[3], const double eb0[3],
                                         const double eb1[3], double eps_x, double H[144]) {
  const double c = edge_edge_cross_squared_norm(ea0, ea1, eb0, eb1);
  if (c >= eps_x) {
    for (int i = 0; i < 144; ++i) H[i] = 0.0;
    return;
  }
  double gc[12];
  edge_edge_cross_squared_norm_gradient(ea0, ea1, eb0, eb1, gc);
  edge_edge_cross_squared_norm_hessian(ea0, ea1, eb0, eb1, H);
  const double dm = mollifier_first_derivative(c, eps_x);
  const double d2m = mollifier_second_derivative(c, eps_x);
  for (int i = 0; i < 12; ++i)
    for (int j = 0; j < 12; ++j) H[12 * i + j] = dm * H[12 * i + j] + d2m * gc[i] * gc[j];
}

}  // namespace dipc::contact
