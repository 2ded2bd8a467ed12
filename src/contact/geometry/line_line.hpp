// Squared distance between the infinite lines through ea0, ea1 and through eb0, eb1:
//   d = ((ea0 - eb0) . n)^2 / |n|^2,  n = (ea1 - ea0) x (eb1 - eb0),
// with its gradient (12) and Hessian (144) w.r.t. [ea0, ea1, eb0, eb1]. The interior case
// of the edge-edge distance; the derivatives are those of squared_normal_component
// (normal_component.hpp) pulled back through r = ea0 - eb0, a = ea1 - ea0, b = eb1 - eb0.
// Undefined for parallel lines (n = 0): the classifier never selects it then, and the
// mollifier (edge_edge_mollifier.hpp) switches the barrier off smoothly as n -> 0.
#pragma once
#include "contact/geometry/chain_rule.hpp"
#include "contact/geometry/normal_component.hpp"
#include "math/host_device.hpp"
#include "math/vector3.hpp"

namespace dipc::contact {

namespace detail {
// J (9 x 12) of r = ea0 - eb0, a = ea1 - ea0, b = eb1 - eb0 w.r.t. [ea0, ea1, eb0, eb1]. A
// local array, not a namespace constant, so CUDA device code can use it.
DIPC_HD void line_line_jacobian(double J[9 * 12]) {
  const double C[] = {1.0,  0.0, -1.0, 0.0,  //
                      -1.0, 1.0, 0.0,  0.0,  //
                      0.0,  0.0, -1.0, 1.0};
  vertex_combination_jacobian(C, 3, 4, J);
}
}  // namespace detail

DIPC_HD double line_line_distance(const double ea0[3], const double ea1[3], const double eb0[3], const double eb1[3]) {
  double r[3], a[3], b[3];
  subtract3(ea0, eb0, r);
  subtract3(ea1, ea0, a);
  subtract3(eb1, eb0, b);
  return squared_normal_component(r, a, b);
}

DIPC_HD void line_line_distance_gradient(const double ea0[3], const double ea1[3], const double eb0[3],
                                         const double eb1[3], double g[12]) {
  double r[3], a[3], b[3], gy[9], J[9 * 12];
  subtract3(ea0, eb0, r);
  subtract3(ea1, ea0, a);
  subtract3(eb1, eb0, b);
  squared_normal_component_gradient(r, a, b, gy);
  detail::line_line_jacobian(J);
  pull_back_gradient(J, 9, 12, gy, g);
}

DIPC_HD void line_line_distance_hessian(const double ea0[3], const double ea1[3], const double eb0[3],
                                        const double eb1[3], double H[144]) {
  double r[3], a[3], b[3], Hy[81], J[9 * 12];
  subtract3(ea0, eb0, r);
  subtract3(ea1, ea0, a);
  subtract3(eb1, eb0, b);
  squared_normal_component_hessian(r, a, b, Hy);
  detail::line_line_jacobian(J);
  pull_back_hessian(J, 9, 12, Hy, H);
}

}  // namespace dipc::contact
