// Orthonormal tangent bases P (3x2, row-major P[2*i + j]) of contact pairs: the columns span
// the plane orthogonal to the contact normal, the plane in which IPC friction acts (Li et
// al. 2020, "Incremental Potential Contact", §5: u = P^T Gamma (x - x_n) is the tangential
// relative displacement). Host/device point functions.
//
// The contact normal is the direction between the two closest points, except in a
// triangle's face region, where the triangle normal is used (the same direction, but exact
// however close the point is), and a degenerate zero-distance configuration, where it falls
// back to the triangle normal (point-triangle) or the edges' common normal (edge-edge).
// IPC Toolkit's point-edge/point-point/edge-edge/point-triangle bases are these same planes.
#pragma once
#include <cmath>

#include "contact/friction/closest_coordinates.hpp"
#include "math/host_device.hpp"
#include "math/vector3.hpp"

namespace dipc::contact {

// P from a non-zero normal n and a preferred first tangent direction `reference`: the first
// column is reference with its normal component removed (Gram-Schmidt), the second is
// n_hat x column 0, so P is orthonormal and right-handed with n. When reference is (nearly)
// parallel to n or zero, the coordinate axis least aligned with n is used instead.
DIPC_HD void tangent_basis_with_reference(const double n[3], const double reference[3], double P[6]) {
  const double nn = sqrt(dot3(n, n));
  const double nh[3] = {n[0] / nn, n[1] / nn, n[2] / nn};
  double t[3];
  const double rn = dot3(reference, nh);
  for (int i = 0; i < 3; ++i) t[i] = reference[i] - rn * nh[i];
  double tt = dot3(t, t);
  // sin^2(angle(reference, n)) below 1e-12: the projected direction has lost most digits.
  if (!(tt > 1e-12 * dot3(reference, reference))) {
    int k = 0;
    for (int i = 1; i < 3; ++i)
      if (fabs(nh[i]) < fabs(nh[k])) k = i;
    for (int i = 0; i < 3; ++i) t[i] = (i == k ? 1.0 : 0.0) - nh[k] * nh[i];
    tt = dot3(t, t);  // >= 2/3: the least aligned axis has |nh_k|^2 <= 1/3
  }
  const double inv = 1.0 / sqrt(tt);
  for (int i = 0; i < 3; ++i) t[i] *= inv;
  double s[3];
  cross3(nh, t, s);
  for (int i = 0; i < 3; ++i) {
    P[2 * i] = t[i];
    P[2 * i + 1] = s[i];
  }
}

// P for a normal alone (obstacle planes): the first tangent is the coordinate axis least
// aligned with n, orthogonalised.
DIPC_HD void tangent_basis_from_normal(const double n[3], double P[6]) {
  const double zero[3] = {0.0, 0.0, 0.0};
  tangent_basis_with_reference(n, zero, P);
}

// Tangent basis of a point-triangle pair at positions (p, t0, t1, t2), given the closest
// feature and barycentric coordinates from point_triangle_closest_coordinates. Face region:
// the plane of the triangle, first tangent along t1 - t0 (as IPC Toolkit). Edge region: the
// plane orthogonal to p - c, first tangent along the edge (orthogonal to p - c already).
// Vertex region: orthogonal to p - c. Zero distance outside the face: triangle plane.
DIPC_HD void point_triangle_tangent_basis(const double p[3], const double t0[3], const double t1[3], const double t2[3],
                                          TriangleFeature feature, const double beta[2], double P[6]) {
  double e01[3], e02[3], e12[3], face_normal[3];
  subtract3(t1, t0, e01);
  subtract3(t2, t0, e02);
  subtract3(t2, t1, e12);
  cross3(e01, e02, face_normal);
  double c[3], pc[3];
  for (int i = 0; i < 3; ++i) c[i] = t0[i] + beta[0] * e01[i] + beta[1] * e02[i];
  subtract3(p, c, pc);
  const double scale2 = dot3(e01, e01) + dot3(e02, e02) + dot3(e12, e12);
  // Distance below 1e-12 of the triangle's size: the direction p - c is rounding noise.
  const bool separated = dot3(pc, pc) > 1e-24 * scale2;
  const bool face_usable = dot3(face_normal, face_normal) > 0.0;
  if (feature == TriangleFeature::kFace || (!separated && face_usable)) {
    tangent_basis_with_reference(face_normal, e01, P);
    return;
  }
  if (!separated) {
    // Zero distance to a zero-area triangle: any plane containing its longest edge.
    const double* edge = e01;
    if (dot3(e02, e02) > dot3(edge, edge)) edge = e02;
    if (dot3(e12, e12) > dot3(edge, edge)) edge = e12;
    double n[3];
    tangent_basis_with_reference(edge, e01, P);
    for (int i = 0; i < 3; ++i) n[i] = P[2 * i];
    tangent_basis_with_reference(n, edge, P);
    return;
  }
  const double* reference = e01;
  if (feature == TriangleFeature::kEdge12) reference = e12;
  if (feature == TriangleFeature::kEdge20) reference = e02;
  tangent_basis_with_reference(pc, reference, P);
}

// Tangent basis of an edge-edge pair, given closest-point parameters from
// edge_edge_closest_coordinates: orthogonal to ca - cb (the closest points). The first
// tangent is along an edge whose closest point is interior (that edge is orthogonal to the
// normal), else along ea. Zero distance: orthogonal to ea x eb, or, for parallel edges,
// a plane containing ea.
DIPC_HD void edge_edge_tangent_basis(const double ea0[3], const double ea1[3], const double eb0[3], const double eb1[3],
                                     double alpha, double beta, double P[6]) {
  double ea[3], eb[3], d[3];
  subtract3(ea1, ea0, ea);
  subtract3(eb1, eb0, eb);
  for (int i = 0; i < 3; ++i) d[i] = (ea0[i] + alpha * ea[i]) - (eb0[i] + beta * eb[i]);
  const double* reference = (alpha > 0.0 && alpha < 1.0) || !(beta > 0.0 && beta < 1.0) ? ea : eb;
  const double scale2 = dot3(ea, ea) + dot3(eb, eb);
  if (dot3(d, d) > 1e-24 * scale2) {
    tangent_basis_with_reference(d, reference, P);
    return;
  }
  double n[3];
  cross3(ea, eb, n);
  if (dot3(n, n) > 1e-14 * dot3(ea, ea) * dot3(eb, eb)) {
    tangent_basis_with_reference(n, ea, P);
    return;
  }
  const double* along = dot3(ea, ea) >= dot3(eb, eb) ? ea : eb;
  if (!(dot3(along, along) > 0.0)) {
    // Both edges are points at the same place: no geometric information at all.
    const double z[3] = {0.0, 0.0, 1.0};
    tangent_basis_from_normal(z, P);
    return;
  }
  tangent_basis_with_reference(along, ea, P);
  for (int i = 0; i < 3; ++i) n[i] = P[2 * i];
  tangent_basis_with_reference(n, along, P);
}

}  // namespace dipc::contact
