// Does a segment cross a triangle? Orientation tests in double precision (the signs of
// Shewchuk's orient3d, without exact arithmetic): used to check the no-intersection invariant
// of contact runs and the initial state, where a robust answer for clear crossings is enough.
#pragma once
#include <algorithm>
#include <cmath>

namespace dipc {

inline double orient3d(const double* a, const double* b, const double* c, const double* d) {
  const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
  const double v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
  const double w[3] = {d[0] - a[0], d[1] - a[1], d[2] - a[2]};
  return u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) + u[2] * (v[0] * w[1] - v[1] * w[0]);
}

// True when segment e0–e1 properly crosses triangle t0 t1 t2: its end points are strictly on
// opposite sides of the triangle's plane and its line passes strictly inside the three
// triangle edges. "Strictly" means beyond a round-off band of 1e-10 · L³ for the orientation
// volumes (L the longest extent of the five points), so nearly coplanar neighbours of a surface
// are not reported; touching configurations are left to the distance check (d_min > 0).
inline bool segment_crosses_triangle(const double* e0, const double* e1, const double* t0, const double* t1,
                                     const double* t2) {
  const double* pts[5] = {e0, e1, t0, t1, t2};
  double L = 0;
  for (int i = 0; i < 5; ++i)
    for (int j = i + 1; j < 5; ++j)
      for (int c = 0; c < 3; ++c) L = std::max(L, std::abs(pts[i][c] - pts[j][c]));
  const double band = 1e-10 * L * L * L;
  const double s0 = orient3d(t0, t1, t2, e0), s1 = orient3d(t0, t1, t2, e1);
  if (!((s0 > band && s1 < -band) || (s0 < -band && s1 > band))) return false;
  const double a = orient3d(e0, e1, t0, t1), b = orient3d(e0, e1, t1, t2), c = orient3d(e0, e1, t2, t0);
  return (a > band && b > band && c > band) || (a < -band && b < -band && c < -band);
}

}  // namespace dipc
