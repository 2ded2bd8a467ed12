// Projection of a symmetric 2x2 matrix onto the positive semi-definite cone, in closed form
// (host/device). Used for the inner 2x2 matrix of the friction Hessian, which is all that
// needs projecting (Li et al. 2020, "Incremental Potential Contact", supplement: the friction
// Hessian Gamma^T P M P^T Gamma is PSD exactly when M is).
#pragma once
#include <cmath>

#include "math/host_device.hpp"

namespace dipc::contact {

// Replaces M = [m0 m1; m2 m3] (symmetric, m1 == m2 read from m1) by V diag(max(lambda, 0)) V^T,
// its nearest PSD matrix in the Frobenius norm (Higham 1988). Eigenvalues lambda1,2 =
// mean -+ r, r = hypot((m0 - m3)/2, m1). With exactly one negative eigenvalue lambda1,
// M - lambda1 I = (lambda2 - lambda1) v2 v2^T, so the projection lambda2 v2 v2^T equals
// lambda2/(lambda2 - lambda1) (M - lambda1 I): no eigenvector is formed, and
// lambda2 - lambda1 = 2r > 0 in that case.
DIPC_HD void project_symmetric_2x2_to_psd(double M[4]) {
  const double a = M[0], b = M[1], c = M[3];
  const double mean = 0.5 * (a + c);
  const double r = hypot(0.5 * (a - c), b);
  const double lo = mean - r, hi = mean + r;
  if (lo >= 0.0) {
    M[2] = b;
    return;
  }
  if (hi <= 0.0) {
    M[0] = M[1] = M[2] = M[3] = 0.0;
    return;
  }
  const double s = hi / (hi - lo);
  M[0] = s * (a - lo);
  M[1] = M[2] = s * b;
  M[3] = s * (c - lo);
}

}  // namespace dipc::contact
