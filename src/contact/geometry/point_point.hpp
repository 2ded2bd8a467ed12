// Squared distance between two points, d = |p - q|^2, with its gradient (6) and Hessian
// (36) w.r.t. [p, q]: g = [2(p - q), -2(p - q)], H = [[2I, -2I], [-2I, 2I]]. The vertex-vertex
// cases of the point-triangle and edge-edge distances.
#pragma once
#include "math/host_device.hpp"
#include "math/vector3.hpp"

namespace dipc::contact {

DIPC_HD double point_point_distance(const double p[3], const double q[3]) {
  double r[3];
  subtract3(p, q, r);
  return squared_norm3(r);
}

DIPC_HD void point_point_distance_gradient(const double p[3], const double q[3], double g[6]) {
  for (int i = 0; i < 3; ++i) {
    g[i] = 2.0 * (p[i] - q[i]);
    g[3 + i] = -g[i];
  }
}

DIPC_HD void point_point_distance_hessian(const double p[3], const double q[3], double H[36]) {
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) {
      const double block_sign = ((i < 3) == (j < 3)) ? 2.0 : -2.0;
      H[6 * i + j] = (i % 3 == j % 3) ? block_sign : 0.0;
    }
}

}  // namespace dipc::contact
