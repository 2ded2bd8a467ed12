// The C^1 friction mollifier of IPC (Li et al. 2020, "Incremental Potential Contact", ACM TOG
// 39(4), §5, the smoothed static friction), as host/device point functions of the tangential
// relative displacement norm y = ||u|| >= 0 and the displacement threshold eps_u = eps_v h.
//
// Coulomb friction's force magnitude is mu*lambda for any sliding speed and anywhere in
// [0, mu*lambda] when sticking; IPC replaces the step by f1, which ramps from 0 to 1 over
// [0, eps_u) and is C^1 at eps_u:
//   f1(y) = -y^2/eps_u^2 + 2 y/eps_u   (y < eps_u),   1   (y >= eps_u),
// and integrates it, f0' = f1, choosing the constant so that f0(y) = y in the sliding regime
// (the paper's and IPC Toolkit's choice, so the dissipated energy is mu*lambda*||u|| there):
//   f0(y) = -y^3/(3 eps_u^2) + y^2/eps_u + eps_u/3   (y < eps_u),   y   (y >= eps_u).
// Hence f0(0) = eps_u/3, the minimum; only derivatives of f0 enter the forces.
#pragma once
#include "math/host_device.hpp"

namespace dipc::contact {

// f0(y): the friction potential's profile (D_k = mu lambda_k f0(||u_k||)).
DIPC_HD double friction_f0(double y, double eps_u) {
  if (y >= eps_u) return y;
  return y * y * (1.0 - y / (3.0 * eps_u)) / eps_u + eps_u / 3.0;
}

// f1(y) = f0'(y): the smoothed friction force magnitude divided by mu*lambda.
DIPC_HD double friction_f1(double y, double eps_u) {
  if (y >= eps_u) return 1.0;
  return y * (2.0 - y / eps_u) / eps_u;
}

// f1'(y) = f0''(y). Continuous at eps_u (both sides 0), so f0 is C^2 and D's Hessian is
// continuous across the stick/slip transition.
DIPC_HD double friction_f1_derivative(double y, double eps_u) {
  if (y >= eps_u) return 0.0;
  return 2.0 * (1.0 - y / eps_u) / eps_u;
}

// f1(y)/y, the factor of the gradient mu lambda f1(y)/y * Gamma^T P u (IPC §5). Finite
// at y = 0, where it equals f1'(0) = 2/eps_u: the stick regime is a linear spring.
DIPC_HD double friction_f1_over_y(double y, double eps_u) {
  if (y >= eps_u) return 1.0 / y;
  return (2.0 - y / eps_u) / eps_u;
}

// (f1'(y) y - f1(y)) / y^3, the coefficient of u u^T in the Hessian's inner 2x2 matrix
// mu lambda [f1(y)/y I + (f1'(y) y - f1(y))/y^3 u u^T] (IPC supplement, friction Hessian).
// Singular at y = 0 like -1/(eps_u^2 y), but multiplied by u u^T = O(y^2) the term vanishes
// there; callers skip it at y = 0. Requires y > 0.
DIPC_HD double friction_f1_derivative_term(double y, double eps_u) {
  if (y >= eps_u) return -1.0 / (y * y * y);
  return -1.0 / (eps_u * eps_u * y);
}

}  // namespace dipc::contact
