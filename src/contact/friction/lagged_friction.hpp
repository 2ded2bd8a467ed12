// The per-pair quantities that lazily lagged IPC friction freezes at the start of a lag
// iteration (Li et al. 2020, "Incremental Potential Contact", §5: the tangent basis, the
// closest-point coordinates that define Gamma, and the normal force magnitude lambda are
// evaluated at the lagged positions x_lag, so the friction potential is a smooth function of
// x alone and Newton sees a true potential). Plain aggregates of doubles, host/device, so
// arrays of them can live in device memory.
#pragma once
#include <cmath>

#include "contact/friction/closest_coordinates.hpp"
#include "contact/friction/relative_velocity.hpp"
#include "contact/friction/tangent_basis.hpp"
#include "math/host_device.hpp"

namespace dipc::contact {

// A point-triangle or edge-edge pair (12 stacked dofs, see relative_velocity.hpp).
struct LaggedPairFriction {
  double weights[4];    // Gamma = [w0 I, w1 I, w2 I, w3 I]
  double basis[6];      // P, 3x2 row-major (P[2*i + j]), orthonormal, orthogonal to the normal
  double normal_force;  // lambda_k >= 0 at x_lag (see friction_normal_force)
  double mu;            // friction coefficient
  double eps_u;         // displacement threshold eps_v * h of the mollifier (> 0)
};

// A point against an obstacle plane (3 dofs, Gamma = I). A moving plane is handled by the
// caller passing x_n shifted by the plane's displacement over the step.
struct LaggedPointPlaneFriction {
  double basis[6];
  double normal_force;
  double mu;
  double eps_u;
};

// Normal force magnitude lambda = -kappa b'(d) 2 sqrt(d) (IPC §5): the barrier's force along
// the contact normal is the derivative of kappa b with respect to the unsquared distance
// sqrt(d), and db/d(sqrt d) = b'(d) 2 sqrt(d) since d is the squared distance. b'(d) <= 0
// inside the activation distance, so lambda >= 0. For an area-weighted barrier
// kappa A_k b(d), pass kappa A_k.
DIPC_HD double friction_normal_force(double kappa, double barrier_derivative, double d) {
  return -kappa * barrier_derivative * 2.0 * sqrt(d);
}

// Lagged data of a point-triangle pair at x_lag = [p, t0, t1, t2].
DIPC_HD LaggedPairFriction point_triangle_lagged_friction(const double x_lag12[12], double mu, double normal_force,
                                                          double eps_u) {
  LaggedPairFriction f;
  double beta[2];
  const TriangleFeature feature = point_triangle_closest_coordinates(x_lag12, x_lag12 + 3, x_lag12 + 6, x_lag12 + 9,
                                                                     beta);
  point_triangle_relative_velocity_weights(beta, f.weights);
  point_triangle_tangent_basis(x_lag12, x_lag12 + 3, x_lag12 + 6, x_lag12 + 9, feature, beta, f.basis);
  f.normal_force = normal_force;
  f.mu = mu;
  f.eps_u = eps_u;
  return f;
}

// Lagged data of an edge-edge pair at x_lag = [ea0, ea1, eb0, eb1].
DIPC_HD LaggedPairFriction edge_edge_lagged_friction(const double x_lag12[12], double mu, double normal_force,
                                                     double eps_u) {
  LaggedPairFriction f;
  double alpha, beta;
  edge_edge_closest_coordinates(x_lag12, x_lag12 + 3, x_lag12 + 6, x_lag12 + 9, &alpha, &beta);
  edge_edge_relative_velocity_weights(alpha, beta, f.weights);
  edge_edge_tangent_basis(x_lag12, x_lag12 + 3, x_lag12 + 6, x_lag12 + 9, alpha, beta, f.basis);
  f.normal_force = normal_force;
  f.mu = mu;
  f.eps_u = eps_u;
  return f;
}

// Lagged data of a point against a plane with (non-zero, any length) normal n.
DIPC_HD LaggedPointPlaneFriction point_plane_lagged_friction(const double normal[3], double mu, double normal_force,
                                                             double eps_u) {
  LaggedPointPlaneFriction f;
  tangent_basis_from_normal(normal, f.basis);
  f.normal_force = normal_force;
  f.mu = mu;
  f.eps_u = eps_u;
  return f;
}

}  // namespace dipc::contact
