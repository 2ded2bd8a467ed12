// Squared distance between a point and a triangle, its gradient (12) and Hessian (144)
// w.r.t. the stacked dofs [p, t0, t1, t2], for a given closest-feature type
// (distance_types.hpp): the type selects the elementary case (point-point, point-line or
// point-plane) and its derivatives are scattered into the 12 dofs. Passing the type
// explicitly lets a caller keep it fixed across a Newton iteration and evaluate value,
// gradient and Hessian of the same smooth piece.
#pragma once
#include <cmath>

#include "contact/geometry/chain_rule.hpp"
#include "contact/geometry/distance_types.hpp"
#include "contact/geometry/point_line.hpp"
#include "contact/geometry/point_plane.hpp"
#include "contact/geometry/point_point.hpp"
#include "math/host_device.hpp"

namespace dipc::contact {

// Stacked vertex indices (0 = p, 1..3 = t0..t2) that the elementary case of `type` takes,
// in its argument order; returns their number (2, 3 or 4), or 0 for an invalid type.
DIPC_HD int point_triangle_type_vertices(PointTriangleType type, int ids[4]) {
  ids[0] = 0;
  switch (type) {
    case PointTriangleType::P_T0: ids[1] = 1; return 2;
    case PointTriangleType::P_T1: ids[1] = 2; return 2;
    case PointTriangleType::P_T2: ids[1] = 3; return 2;
    case PointTriangleType::P_E0:
      ids[1] = 1;
      ids[2] = 2;
      return 3;
    case PointTriangleType::P_E1:
      ids[1] = 2;
      ids[2] = 3;
      return 3;
    case PointTriangleType::P_E2:
      ids[1] = 3;
      ids[2] = 1;
      return 3;
    case PointTriangleType::P_T:
      ids[1] = 1;
      ids[2] = 2;
      ids[3] = 3;
      return 4;
  }
  return 0;
}

// NaN for an invalid type, so a corrupted type cannot pass as a distance.
DIPC_HD double point_triangle_distance(const double p[3], const double t0[3], const double t1[3], const double t2[3],
                                       PointTriangleType type) {
  const double* x[4] = {p, t0, t1, t2};
  int ids[4];
  switch (point_triangle_type_vertices(type, ids)) {
    case 2: return point_point_distance(x[ids[0]], x[ids[1]]);
    case 3: return point_line_distance(x[ids[0]], x[ids[1]], x[ids[2]]);
    case 4: return point_plane_distance(p, t0, t1, t2);
  }
  return NAN;
}

// The distance with the type classified here.
DIPC_HD double point_triangle_distance(const double p[3], const double t0[3], const double t1[3], const double t2[3]) {
  return point_triangle_distance(p, t0, t1, t2, point_triangle_distance_type(p, t0, t1, t2));
}

DIPC_HD void point_triangle_distance_gradient(const double p[3], const double t0[3], const double t1[3],
                                              const double t2[3], PointTriangleType type, double g[12]) {
  const double* x[4] = {p, t0, t1, t2};
  int ids[4];
  double g_local[12];
  const int n = point_triangle_type_vertices(type, ids);
  switch (n) {
    case 2: point_point_distance_gradient(x[ids[0]], x[ids[1]], g_local); break;
    case 3: point_line_distance_gradient(x[ids[0]], x[ids[1]], x[ids[2]], g_local); break;
    case 4: point_plane_distance_gradient(p, t0, t1, t2, g_local); break;
    default:
      for (int i = 0; i < 12; ++i) g[i] = NAN;
      return;
  }
  scatter_stacked_gradient(g_local, ids, n, g);
}

DIPC_HD void point_triangle_distance_hessian(const double p[3], const double t0[3], const double t1[3],
                                             const double t2[3], PointTriangleType type, double H[144]) {
  const double* x[4] = {p, t0, t1, t2};
  int ids[4];
  double H_local[144];
  const int n = point_triangle_type_vertices(type, ids);
  switch (n) {
    case 2: point_point_distance_hessian(x[ids[0]], x[ids[1]], H_local); break;
    case 3: point_line_distance_hessian(x[ids[0]], x[ids[1]], x[ids[2]], H_local); break;
    case 4: point_plane_distance_hessian(p, t0, t1, t2, H_local); break;
    default:
      for (int i = 0; i < 144; ++i) H[i] = NAN;
      return;
  }
  scatter_stacked_hessian(H_local, ids, n, H);
}

}  // namespace dipc::contact
