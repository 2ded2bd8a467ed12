// Three-component vector helpers on plain double[3] arrays for the CCD point functions.
// Kept inside ccd/ (namespace dipc::contact::ccd) so the narrow phase depends on nothing
// but host_device.hpp and compiles unchanged in CUDA kernels.
#pragma once
#include "host_device.hpp"

namespace dipc::contact::ccd {

DIPC_HD double dot3(const double a[3], const double b[3]) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

DIPC_HD void sub3(const double a[3], const double b[3], double out[3]) {
  out[0] = a[0] - b[0];
  out[1] = a[1] - b[1];
  out[2] = a[2] - b[2];
}

DIPC_HD void cross3(const double a[3], const double b[3], double out[3]) {
  out[0] = a[1] * b[2] - a[2] * b[1];
  out[1] = a[2] * b[0] - a[0] * b[2];
  out[2] = a[0] * b[1] - a[1] * b[0];
}

DIPC_HD double clamp01(double x) { return x < 0.0 ? 0.0 : (x > 1.0 ? 1.0 : x); }

}  // namespace dipc::contact::ccd
