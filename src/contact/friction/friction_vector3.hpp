// Tiny 3-vector helpers on plain arrays for the friction point functions (host/device).
// Kept in a detail namespace so they cannot clash with other contact headers' helpers.
#pragma once
#include <cmath>

#include "host_device.hpp"

namespace dipc::contact::friction_detail {

DIPC_HD double dot3(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

DIPC_HD void sub3(const double a[3], const double b[3], double out[3]) {
  for (int i = 0; i < 3; ++i) out[i] = a[i] - b[i];
}

DIPC_HD void cross3(const double a[3], const double b[3], double out[3]) {
  out[0] = a[1] * b[2] - a[2] * b[1];
  out[1] = a[2] * b[0] - a[0] * b[2];
  out[2] = a[0] * b[1] - a[1] * b[0];
}

DIPC_HD double clamp01(double s) { return s < 0.0 ? 0.0 : (s > 1.0 ? 1.0 : s); }

}  // namespace dipc::contact::friction_detail
