// Does a segment cross a triangle? Orientation tests in double precision (the signs of
// Shewchuk's orient3d, without exact arithmetic): used to check the no-intersection invariant
// of contact runs and the initial state, where a robust answer for clear crossings is enough.
#pragma once
#include <algorithm>
#include <cmath>

#include "math/vector3.hpp"

namespace dipc {

// (b − a) · ((c − a) × (d − a)), six times the signed volume of the tetrahedron.
inline double orient3d(const double* a, const double* b, const double* c, const double* d) {
  double u[3], v[3], w[3], vxw[3];
  subtract3(b, a, u);
  subtract3(c, a, v);
  subtract3(d, a, w);
  cross3(v, w, vxw);
  return dot3(u, vxw);
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
