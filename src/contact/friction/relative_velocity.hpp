// The relative-velocity operator Gamma of a contact pair (Li et al. 2020, "Incremental
// Potential Contact", §5): with closest-point coordinates frozen, the velocity of the first
// closest point minus that of the second is Gamma v for the pair's stacked 12-dof velocity v.
// For both 12-dof pair types Gamma = [w0 I3, w1 I3, w2 I3, w3 I3], so it is stored as the
// four weights w (host/device point functions):
//   point-triangle [p, t0, t1, t2]:   w = (1, -(1 - beta1 - beta2), -beta1, -beta2)
//                                     (p minus the barycentric point of the triangle);
//   edge-edge [ea0, ea1, eb0, eb1]:   w = (1 - alpha, alpha, -(1 - beta), -beta).
// The weights sum to 0, so Gamma annihilates rigid translations and the friction forces
// Gamma^T f on the four points sum to zero (momentum is conserved).
// Point-plane pairs have Gamma = I3 on the point's 3 dofs (a fixed plane has no velocity).
#pragma once
#include "math/host_device.hpp"

namespace dipc::contact {

DIPC_HD void point_triangle_relative_velocity_weights(const double beta[2], double w[4]) {
  w[0] = 1.0;
  w[1] = -(1.0 - beta[0] - beta[1]);
  w[2] = -beta[0];
  w[3] = -beta[1];
}

DIPC_HD void edge_edge_relative_velocity_weights(double alpha, double beta, double w[4]) {
  w[0] = 1.0 - alpha;
  w[1] = alpha;
  w[2] = -(1.0 - beta);
  w[3] = -beta;
}

// r = Gamma v (3 values) for a stacked 12-vector v.
DIPC_HD void apply_relative_velocity(const double w[4], const double v12[12], double r[3]) {
  for (int a = 0; a < 3; ++a) r[a] = w[0] * v12[a] + w[1] * v12[3 + a] + w[2] * v12[6 + a] + w[3] * v12[9 + a];
}

// out = Gamma^T f (12 values): distributes a force on the relative motion to the 4 points.
DIPC_HD void apply_relative_velocity_transpose(const double w[4], const double f[3], double out12[12]) {
  for (int i = 0; i < 4; ++i)
    for (int a = 0; a < 3; ++a) out12[3 * i + a] = w[i] * f[a];
}

}  // namespace dipc::contact
