// IPC's smoothly clamped log barrier (Li et al. 2020, "Incremental Potential Contact", ACM
// TOG 39(4), §4), here on squared distances d and squared activation distance d_hat as in
// IPC Toolkit:
//   b(d; d_hat) = -(d - d_hat)^2 ln(d / d_hat)  for 0 < d < d_hat,  0 for d >= d_hat,
//   b'  = -2 (d - d_hat) ln(d / d_hat) - (d - d_hat)^2 / d,
//   b'' = -2 ln(d / d_hat) - (d - d_hat)(3 d + d_hat) / d^2.
// b, b' and b'' all vanish at d = d_hat, so the barrier is C2 across the activation
// distance; b -> +inf as d -> 0. For d <= 0 (contact or penetration, outside the domain)
// b = +inf, b' = -inf, b'' = +inf, so a line search rejects such a state. Contact
// stiffness kappa and the area weights are applied by the caller.
#pragma once
#include <cmath>

#include "math/host_device.hpp"

namespace dipc::contact {

namespace detail {
// ln(d / d_hat). Near d_hat, log1p of the exactly computed relative gap (d - d_hat) / d_hat
// keeps full relative accuracy of the small logarithm (log of the rounded ratio would
// not); far below d_hat the ratio is accurate and log1p's argument would not be.
DIPC_HD double log_ratio(double d, double dhat) {
  if (d > 0.5 * dhat) return log1p((d - dhat) / dhat);
  return log(d / dhat);
}
}  // namespace detail

DIPC_HD double barrier(double d, double dhat) {
  if (d >= dhat) return 0.0;
  if (d <= 0.0) return INFINITY;
  const double gap = d - dhat;
  return -gap * gap * detail::log_ratio(d, dhat);
}

DIPC_HD double barrier_first_derivative(double d, double dhat) {
  if (d >= dhat) return 0.0;
  if (d <= 0.0) return -INFINITY;
  const double gap = d - dhat;
  return -gap * (2.0 * detail::log_ratio(d, dhat) + gap / d);
}

DIPC_HD double barrier_second_derivative(double d, double dhat) {
  if (d >= dhat) return 0.0;
  if (d <= 0.0) return INFINITY;
  const double gap = d - dhat;
  return -2.0 * detail::log_ratio(d, dhat) - gap * (3.0 * d + dhat) / (d * d);
}

}  // namespace dipc::contact
