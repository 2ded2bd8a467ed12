// Squared distance from a point p to the plane through t0, t1, t2:
//   d = ((p - t0) . n)^2 / |n|^2,  n = (t1 - t0) x (t2 - t0),
// with its gradient (12) and Hessian (144) w.r.t. [p, t0, t1, t2]. The face case of the
// point-triangle distance; the derivatives are those of squared_normal_component
// (normal_component.hpp) pulled back through r = p - t0, a = t1 - t0, b = t2 - t0.
// Undefined for a degenerate triangle (n = 0): the classifier never selects it then.
#pragma once
#include "contact/geometry/chain_rule.hpp"
#include "contact/geometry/normal_component.hpp"
#include "math/host_device.hpp"
#include "math/vector3.hpp"

namespace dipc::contact {

namespace detail {
// J (9 x 12) of r = p - t0, a = t1 - t0, b = t2 - t0 w.r.t. [p, t0, t1, t2]. A local array,
// not a namespace constant, so CUDA device code can use it.
DIPC_HD void point_plane_jacobian(double J[9 * 12]) {
  const double C[] = {1.0, -1.0, 0.0, 0.0,  //
                      0.0, -1.0, 1.0, 0.0,  //
                      0.0, -1.0, 0.0, 1.0};
  vertex_combination_jacobian(C, 3, 4, J);
}
}  // namespace detail

DIPC_HD double point_plane_distance(const double p[3], const double t0[3], const double t1[3], const double t2[3]) {
  double r[3], a[3], b[3];
  subtract3(p, t0, r);
  subtract3(t1, t0, a);
  subtract3(t2, t0, b);
  return squared_normal_component(r, a, b);
}

DIPC_HD void point_plane_distance_gradient(const double p[3], const double t0[3], const double t1[3],
                                           const double t2[3], double g[12]) {
  double r[3], a[3], b[3], gy[9], J[9 * 12];
  subtract3(p, t0, r);
  subtract3(t1, t0, a);
  subtract3(t2, t0, b);
  squared_normal_component_gradient(r, a, b, gy);
  detail::point_plane_jacobian(J);
  pull_back_gradient(J, 9, 12, gy, g);
}

DIPC_HD void point_plane_distance_hessian(const double p[3], const double t0[3], const double t1[3], const double t2[3],
                                          double H[144]) {
  double r[3], a[3], b[3], Hy[81], J[9 * 12];
  subtract3(p, t0, r);
  subtract3(t1, t0, a);
  subtract3(t2, t0, b);
  squared_normal_component_hessian(r, a, b, Hy);
  detail::point_plane_jacobian(J);
  pull_back_hessian(J, 9, 12, Hy, H);
}

}  // namespace dipc::contact
