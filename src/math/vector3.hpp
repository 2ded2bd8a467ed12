// The one 3-vector of dipc: dot and cross products, differences, the cross-product matrix, on
// plain double[3] arrays (matrices row-major, A[3*i + j] = A_ij), so the same code runs on the
// host and in CUDA kernels (contact geometry, CCD, friction; host code with std::array<double, 3>
// passes .data()). The CCD relies on host and device rounding alike: keep these free of fused
// operations the compiler could form differently (its kernels build with --fmad=false).
#pragma once
#include <cmath>

#include "math/host_device.hpp"

namespace dipc {

DIPC_HD double dot3(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

DIPC_HD double squared_norm3(const double a[3]) { return dot3(a, a); }

// c = a - b
DIPC_HD void subtract3(const double a[3], const double b[3], double c[3]) {
  for (int i = 0; i < 3; ++i) c[i] = a[i] - b[i];
}

// c = a x b (c must not alias a or b)
DIPC_HD void cross3(const double a[3], const double b[3], double c[3]) {
  c[0] = a[1] * b[2] - a[2] * b[1];
  c[1] = a[2] * b[0] - a[0] * b[2];
  c[2] = a[0] * b[1] - a[1] * b[0];
}

DIPC_HD double clamp01(double s) { return s < 0.0 ? 0.0 : (s > 1.0 ? 1.0 : s); }

// [a]_x, the matrix with [a]_x v = a x v.
DIPC_HD void cross_matrix3(const double a[3], double A[9]) {
  A[0] = 0.0;
  A[1] = -a[2];
  A[2] = a[1];
  A[3] = a[2];
  A[4] = 0.0;
  A[5] = -a[0];
  A[6] = -a[1];
  A[7] = a[0];
  A[8] = 0.0;
}

// Solid angle of triangle (a, b, c) seen from the origin (Van Oosterom & Strackee 1983, "The
// solid angle of a plane triangle"), positive when the triangle's right-hand normal points away
// from the origin; the winding numbers of closed surfaces sum it.
DIPC_HD double solid_angle3(const double a[3], const double b[3], const double c[3]) {
  const double la = sqrt(dot3(a, a)), lb = sqrt(dot3(b, b)), lc = sqrt(dot3(c, c));
  double bxc[3];
  cross3(b, c, bxc);
  const double triple = dot3(a, bxc);
  const double denominator = la * lb * lc + dot3(a, b) * lc + dot3(b, c) * la + dot3(c, a) * lb;
  return 2.0 * atan2(triple, denominator);
}

}  // namespace dipc
