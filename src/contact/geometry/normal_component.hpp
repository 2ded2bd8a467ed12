// f(r, a, b) = (r . n)^2 / |n|^2 with n = a x b: the squared length of the component of r
// along the normal of the plane spanned by a and b. Both the point-plane distance
// (r = p - t0, a = t1 - t0, b = t2 - t0) and the line-line distance (r = ea0 - eb0,
// a = ea1 - ea0, b = eb1 - eb0) are this function of different vertex differences.
// Variables stacked as x = [r, a, b] (9); derivatives taken through y = [r, n] (6).
//
// With w = r . n, q = n . n and lambda = w / q (so f = w lambda):
//   df/dr = 2 lambda n,            df/dn = 2 lambda (r - lambda n),
//   d(lambda)/dn = (r - 2 lambda n) / q, hence
//   H_rr = 2 n n^T / q,  H_rn = 2 lambda I + 2 n (r - 2 lambda n)^T / q,
//   H_nn = 2 (r - 2 lambda n)(r - 2 lambda n)^T / q - 2 lambda^2 I,
// then pulled back through n = a x b (cross_product_derivatives.hpp). Undefined for
// parallel a, b (q = 0): the distance classifiers never select these cases then.
#pragma once
#include "contact/geometry/chain_rule.hpp"
#include "contact/geometry/cross_product_derivatives.hpp"
#include "math/host_device.hpp"
#include "math/vector3.hpp"

namespace dipc::contact {

DIPC_HD double squared_normal_component(const double r[3], const double a[3], const double b[3]) {
  double n[3];
  cross3(a, b, n);
  const double w = dot3(r, n);
  return w * w / squared_norm3(n);
}

DIPC_HD void squared_normal_component_gradient(const double r[3], const double a[3], const double b[3], double g[9]) {
  double n[3], gn[3], an[3], nb[3];
  cross3(a, b, n);
  const double lambda = dot3(r, n) / squared_norm3(n);
  for (int i = 0; i < 3; ++i) {
    g[i] = 2.0 * lambda * n[i];
    gn[i] = 2.0 * lambda * (r[i] - lambda * n[i]);
  }
  // g_a = (dn/da)^T g_n = b x g_n, g_b = (dn/db)^T g_n = g_n x a.
  cross3(b, gn, an);
  cross3(gn, a, nb);
  for (int i = 0; i < 3; ++i) {
    g[3 + i] = an[i];
    g[6 + i] = nb[i];
  }
}

DIPC_HD void squared_normal_component_hessian(const double r[3], const double a[3], const double b[3], double H[81]) {
  double n[3];
  cross3(a, b, n);
  const double q = squared_norm3(n);
  const double lambda = dot3(r, n) / q;
  double s[3], gn[3];
  for (int i = 0; i < 3; ++i) {
    s[i] = r[i] - 2.0 * lambda * n[i];
    gn[i] = 2.0 * lambda * (r[i] - lambda * n[i]);
  }
  double Hy[36];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      const double delta = (i == j) ? 1.0 : 0.0;
      const double H_rn = 2.0 * lambda * delta + 2.0 * n[i] * s[j] / q;
      Hy[i * 6 + j] = 2.0 * n[i] * n[j] / q;
      Hy[i * 6 + 3 + j] = H_rn;
      Hy[(3 + j) * 6 + i] = H_rn;
      Hy[(3 + i) * 6 + 3 + j] = 2.0 * s[i] * s[j] / q - 2.0 * lambda * lambda * delta;
    }
  // y = [r, n] from x = [r, a, b]: identity on r, the cross-product Jacobian on n.
  double J[6 * 9] = {};
  for (int i = 0; i < 3; ++i) J[i * 9 + i] = 1.0;
  write_cross_product_jacobian(a, b, J, 9, 3, 3, 6);
  pull_back_hessian(J, 6, 9, Hy, H);
  add_cross_product_curvature(gn, H, 9, 3, 6);
}

}  // namespace dipc::contact
