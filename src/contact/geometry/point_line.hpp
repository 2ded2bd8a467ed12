// Squared distance from a point p to the infinite line through e0 and e1, with its gradient
// (9) and Hessian (81) w.r.t. [p, e0, e1]. The point-edge cases of the point-triangle and
// edge-edge distances (used only when the closest point is inside the edge, where the
// line and segment distances agree).
//
// With r = p - e0, e = e1 - e0, q = e . e, sigma = r . e / q (the line parameter of the
// foot point) and r_perp = r - sigma e:
//   d = |r_perp|^2, evaluated as |r x e|^2 / q, which has no cancellation when p is close
//   to the line far from e0 (|r|^2 - (r . e)^2 / q would lose digits there);
//   dd/dr = 2 r_perp,  dd/de = -2 sigma r_perp;
//   with w = r - 2 sigma e (so d(sigma)/de = w / q):
//   H_rr = 2 (I - e e^T / q),  H_re = -2 sigma I - 2 e w^T / q,  H_ee = 2 sigma^2 I - 2 w w^T / q,
// pulled back through r = p - e0, e = e1 - e0. Undefined for e0 = e1 (the classifiers
// select a point-point case then).
#pragma once
#include "contact/geometry/chain_rule.hpp"
#include "math/host_device.hpp"
#include "math/vector3.hpp"

namespace dipc::contact {

namespace detail {
// J (6 x 9) of r = p - e0, e = e1 - e0 w.r.t. [p, e0, e1]. A local array, not a namespace
// constant, so CUDA device code can use it.
DIPC_HD void point_line_jacobian(double J[6 * 9]) {
  const double C[] = {1.0, -1.0, 0.0, 0.0, -1.0, 1.0};
  vertex_combination_jacobian(C, 2, 3, J);
}
}  // namespace detail

DIPC_HD double point_line_distance(const double p[3], const double e0[3], const double e1[3]) {
  double r[3], e[3], m[3];
  subtract3(p, e0, r);
  subtract3(e1, e0, e);
  cross3(r, e, m);
  return squared_norm3(m) / squared_norm3(e);
}

DIPC_HD void point_line_distance_gradient(const double p[3], const double e0[3], const double e1[3], double g[9]) {
  double r[3], e[3];
  subtract3(p, e0, r);
  subtract3(e1, e0, e);
  const double sigma = dot3(r, e) / squared_norm3(e);
  double gy[6];
  for (int i = 0; i < 3; ++i) {
    const double r_perp = r[i] - sigma * e[i];
    gy[i] = 2.0 * r_perp;
    gy[3 + i] = -2.0 * sigma * r_perp;
  }
  double J[6 * 9];
  detail::point_line_jacobian(J);
  pull_back_gradient(J, 6, 9, gy, g);
}

DIPC_HD void point_line_distance_hessian(const double p[3], const double e0[3], const double e1[3], double H[81]) {
  double r[3], e[3];
  subtract3(p, e0, r);
  subtract3(e1, e0, e);
  const double q = squared_norm3(e);
  const double sigma = dot3(r, e) / q;
  double w[3];
  for (int i = 0; i < 3; ++i) w[i] = r[i] - 2.0 * sigma * e[i];
  double Hy[36];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      const double delta = (i == j) ? 1.0 : 0.0;
      const double H_re = -2.0 * sigma * delta - 2.0 * e[i] * w[j] / q;
      Hy[i * 6 + j] = 2.0 * (delta - e[i] * e[j] / q);
      Hy[i * 6 + 3 + j] = H_re;
      Hy[(3 + j) * 6 + i] = H_re;
      Hy[(3 + i) * 6 + 3 + j] = 2.0 * sigma * sigma * delta - 2.0 * w[i] * w[j] / q;
    }
  double J[6 * 9];
  detail::point_line_jacobian(J);
  pull_back_hessian(J, 6, 9, Hy, H);
}

}  // namespace dipc::contact
