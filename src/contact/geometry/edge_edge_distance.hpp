// Squared distance between two edges (segments), its gradient (12) and Hessian (144)
// w.r.t. the stacked dofs [ea0, ea1, eb0, eb1], for a given closest-feature type
// (distance_types.hpp): the type selects the elementary case (point-point, point-line or
// line-line) and its derivatives are scattered into the 12 dofs. For nearly parallel edges
// the barrier multiplies this distance's barrier by the mollifier (edge_edge_mollifier.hpp).
#pragma once
#include <cmath>

#include "contact/geometry/chain_rule.hpp"
#include "contact/geometry/distance_types.hpp"
#include "contact/geometry/line_line.hpp"
#include "contact/geometry/point_line.hpp"
#include "contact/geometry/point_point.hpp"
#include "math/host_device.hpp"

namespace dipc::contact {

// Stacked vertex indices (0 = ea0, 1 = ea1, 2 = eb0, 3 = eb1) that the elementary case of
// `type` takes, in its argument order (point first for point-line); returns their number
// (2, 3 or 4), or 0 for an invalid type.
DIPC_HD int edge_edge_type_vertices(EdgeEdgeType type, int ids[4]) {
  switch (type) {
    case EdgeEdgeType::EA0_EB0:
      ids[0] = 0;
      ids[1] = 2;
      return 2;
    case EdgeEdgeType::EA0_EB1:
      ids[0] = 0;
      ids[1] = 3;
      return 2;
    case EdgeEdgeType::EA1_EB0:
      ids[0] = 1;
      ids[1] = 2;
      return 2;
    case EdgeEdgeType::EA1_EB1:
      ids[0] = 1;
      ids[1] = 3;
      return 2;
    case EdgeEdgeType::EA_EB0:
      ids[0] = 2;
      ids[1] = 0;
      ids[2] = 1;
      return 3;
    case EdgeEdgeType::EA_EB1:
      ids[0] = 3;
      ids[1] = 0;
      ids[2] = 1;
      return 3;
    case EdgeEdgeType::EA0_EB:
      ids[0] = 0;
      ids[1] = 2;
      ids[2] = 3;
      return 3;
    case EdgeEdgeType::EA1_EB:
      ids[0] = 1;
      ids[1] = 2;
      ids[2] = 3;
      return 3;
    case EdgeEdgeType::EA_EB:
      ids[0] = 0;
      ids[1] = 1;
      ids[2] = 2;
      ids[3] = 3;
      return 4;
  }
  return 0;
}

// NaN for an invalid type, so a corrupted type cannot pass as a distance.
DIPC_HD double edge_edge_distance(const double ea0[3], const double ea1[3], const double eb0[3], const double eb1[3],
                                  EdgeEdgeType type) {
  const double* x[4] = {ea0, ea1, eb0, eb1};
  int ids[4];
  switch (edge_edge_type_vertices(type, ids)) {
    case 2: return point_point_distance(x[ids[0]], x[ids[1]]);
    case 3: return point_line_distance(x[ids[0]], x[ids[1]], x[ids[2]]);
    case 4: return line_line_distance(ea0, ea1, eb0, eb1);
  }
  return NAN;
}

// The distance with the type classified here.
DIPC_HD double edge_edge_distance(const double ea0[3], const double ea1[3], const double eb0[3], const double eb1[3]) {
  return edge_edge_distance(ea0, ea1, eb0, eb1, edge_edge_distance_type(ea0, ea1, eb0, eb1));
}

DIPC_HD void edge_edge_distance_gradient(const double ea0[3], const double ea1[3], const double eb0[3],
                                         const double eb1[3], EdgeEdgeType type, double g[12]) {
  const double* x[4] = {ea0, ea1, eb0, eb1};
  int ids[4];
  double g_local[12];
  const int n = edge_edge_type_vertices(type, ids);
  switch (n) {
    case 2: point_point_distance_gradient(x[ids[0]], x[ids[1]], g_local); break;
    case 3: point_line_distance_gradient(x[ids[0]], x[ids[1]], x[ids[2]], g_local); break;
    case 4: line_line_distance_gradient(ea0, ea1, eb0, eb1, g_local); break;
    default:
      for (int i = 0; i < 12; ++i) g[i] = NAN;
      return;
  }
  scatter_stacked_gradient(g_local, ids, n, g);
}

DIPC_HD void edge_edge_distance_hessian(const double ea0[3], const double ea1[3], const double eb0[3],
                                        const double eb1[3], EdgeEdgeType type, double H[144]) {
  const double* x[4] = {ea0, ea1, eb0, eb1};
  int ids[4];
  double H_local[144];
  const int n = edge_edge_type_vertices(type, ids);
  switch (n) {
    case 2: point_point_distance_hessian(x[ids[0]], x[ids[1]], H_local); break;
    case 3: point_line_distance_hessian(x[ids[0]], x[ids[1]], x[ids[2]], H_local); break;
    case 4: line_line_distance_hessian(ea0, ea1, eb0, eb1, H_local); break;
    default:
      for (int i = 0; i < 144; ++i) H[i] = NAN;
      return;
  }
  scatter_stacked_hessian(H_local, ids, n, H);
}

}  // namespace dipc::contact
