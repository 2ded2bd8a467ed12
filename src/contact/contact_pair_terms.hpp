// One contact pair of the barrier potential as host/device point functions: its squared
// distance, its barrier energy, gradient and PSD-projected Hessian, and its CCD time of impact.
// ContactForm calls them in its CPU loops and the CUDA kernels (cuda/contact_kernels.cu) call
// the very same functions, so both evaluate one formula with one rounding.
//
// A pair's kind (pair_kind.hpp) says what its stacked positions X hold; vertex–plane pairs also
// take the plane's point and unit normal (3 doubles each; the solid side lies behind the
// normal), the others ignore them. Distances are squared, as the barrier's d and d̂ (docs/design.md §1.3).
#pragma once
#include "contact/ccd/time_of_impact.hpp"
#include "contact/geometry/barrier.hpp"
#include "contact/geometry/edge_edge_distance.hpp"
#include "contact/geometry/edge_edge_mollifier.hpp"
#include "contact/geometry/point_triangle_distance.hpp"
#include "contact/geometry/translation_free_psd.hpp"
#include "contact/pair_kind.hpp"
#include "math/host_device.hpp"
#include "math/symmetric_eigen.hpp"
#include "math/vector3.hpp"

namespace dipc {

// Energy, gradient (12 or 3 dofs) and Hessian (12×12 or 3×3, row-major) of one pair. g and H
// are written only for an active pair (and only when asked for) and are otherwise left
// uninitialised: zeroing 156 doubles per pair would cost a kernel more than the distance does.
struct ContactPairTerms {
  double energy = 0;
  double g[12];
  double H[144];
};

// Signed distance of a point from a plane (positive on the open side): s = (x − o)·n.
DIPC_HD double contact_plane_offset(const double* x, const double* plane_point, const double* plane_normal) {
  double r[3];
  subtract3(x, plane_point, r);
  return dot3(r, plane_normal);
}

// Squared distance d of the pair at X (the exact IPC distances of contact/geometry, not the
// CCD's robust ones). For a plane pair d = s² with s the signed offset, so a vertex behind the
// plane still gets a positive d: callers that must reject it test the offset.
DIPC_HD double contact_pair_squared_distance(PairKind kind, const double* X, const double* plane_point,
                                             const double* plane_normal) {
  if (kind == PairKind::vertex_triangle)
    return contact::point_triangle_distance(X, X + 3, X + 6, X + 9,
                                            contact::point_triangle_distance_type(X, X + 3, X + 6, X + 9));
  if (kind == PairKind::edge_edge)
    return contact::edge_edge_distance(X, X + 3, X + 6, X + 9,
                                       contact::edge_edge_distance_type(X, X + 3, X + 6, X + 9));
  const double s = contact_plane_offset(X, plane_point, plane_normal);
  return s * s;
}

// The barrier terms of one pair, e = κ w m(x) b(d(x)) (Li et al. 2020, "Incremental Potential
// Contact", §4; m the edge–edge mollifier of §4.3 below the threshold eps_x, 1 otherwise), with
// d̂² = dhat2, weight w and stiffness κ = kappa:
//   ∇e  = κ w (m b' ∇d + b ∇m),
//   ∇²e = κ w (m (b'' ∇d ∇dᵀ + b' ∇²d) + b' (∇m ∇dᵀ + ∇d ∇mᵀ) + b ∇²m),
// the Hessian projected onto the PSD cone when `project` (per pair, as IPC does, so Newton's
// matrix stays positive semi-definite; four-point pairs on the 9 dimensions their translations
// leave, translation_free_psd.hpp). Returns false when the pair is not admissible
// (d ≤ 0, or a vertex on or behind its plane); *active is false when d ≥ d̂² (the terms are then
// left untouched: energy 0, no gradient or Hessian) and when the pair is not admissible.
DIPC_HD bool contact_pair_terms(PairKind kind, const double* X, const double* plane_point, const double* plane_normal,
                                double dhat2, double kappa, double weight, double eps_x, bool want_g, bool want_H,
                                bool project, bool* active, ContactPairTerms* t) {
  *active = false;
  const int ndof = 3 * pair_node_count(kind);
  double d = 0, gd[12] = {}, Hd[144] = {};
  if (kind == PairKind::vertex_triangle) {
    const auto type = contact::point_triangle_distance_type(X, X + 3, X + 6, X + 9);
    d = contact::point_triangle_distance(X, X + 3, X + 6, X + 9, type);
    if (d >= dhat2) return true;
    if (d <= 0) return false;
    if (want_g || want_H) contact::point_triangle_distance_gradient(X, X + 3, X + 6, X + 9, type, gd);
    if (want_H) contact::point_triangle_distance_hessian(X, X + 3, X + 6, X + 9, type, Hd);
  } else if (kind == PairKind::edge_edge) {
    const auto type = contact::edge_edge_distance_type(X, X + 3, X + 6, X + 9);
    d = contact::edge_edge_distance(X, X + 3, X + 6, X + 9, type);
    if (d >= dhat2) return true;
    if (d <= 0) return false;
    if (want_g || want_H) contact::edge_edge_distance_gradient(X, X + 3, X + 6, X + 9, type, gd);
    if (want_H) contact::edge_edge_distance_hessian(X, X + 3, X + 6, X + 9, type, Hd);
  } else {
    // d = s², ∇d = 2 s n, ∇²d = 2 n nᵀ.
    const double s = contact_plane_offset(X, plane_point, plane_normal);
    if (s <= 0) return false;
    d = s * s;
    if (d >= dhat2) return true;
    for (int c = 0; c < 3; ++c) gd[c] = 2 * s * plane_normal[c];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) Hd[3 * i + j] = 2 * plane_normal[i] * plane_normal[j];
  }
  *active = true;
  const double b = contact::barrier(d, dhat2), b1 = contact::barrier_first_derivative(d, dhat2),
               b2 = contact::barrier_second_derivative(d, dhat2);
  const double s = kappa * weight;
  double m = 1, gm[12] = {}, Hm[144] = {};
  const bool mollified = kind == PairKind::edge_edge &&
                         contact::edge_edge_cross_squared_norm(X, X + 3, X + 6, X + 9) < eps_x;
  if (mollified) {
    m = contact::edge_edge_mollifier(X, X + 3, X + 6, X + 9, eps_x);
    if (want_g || want_H) contact::edge_edge_mollifier_gradient(X, X + 3, X + 6, X + 9, eps_x, gm);
    if (want_H) contact::edge_edge_mollifier_hessian(X, X + 3, X + 6, X + 9, eps_x, Hm);
  }
  t->energy = s * m * b;
  if (want_g || want_H)
    for (int i = 0; i < ndof; ++i) t->g[i] = s * (m * b1 * gd[i] + b * gm[i]);
  if (want_H) {
    for (int i = 0; i < ndof; ++i)
      for (int j = 0; j < ndof; ++j) {
        const double bij = b2 * gd[i] * gd[j] + b1 * Hd[ndof * i + j];  // ∇²b
        t->H[ndof * i + j] = s * (m * bij + b1 * (gm[i] * gd[j] + gd[i] * gm[j]) + b * Hm[ndof * i + j]);
      }
    if (project) {
      if (ndof == 12)
        contact::project_translation_free_psd(t->H);
      else
        project_psd<3>(t->H, 3);
    }
  }
  return true;
}

// Conservative time of impact of the pair moving linearly from X0 (t = 0) to X1 (t = 1),
// searched on [0, t_max] with no safety gap (contact/ccd/time_of_impact.hpp states the
// contract): additive CCD for vertex–triangle and edge–edge pairs, closed form for planes.
DIPC_HD double contact_pair_time_of_impact(PairKind kind, const double* X0, const double* X1, const double* plane_point,
                                           const double* plane_normal, double t_max) {
  if (kind == PairKind::vertex_triangle)
    return contact::point_triangle_time_of_impact(X0, X0 + 3, X0 + 6, X0 + 9, X1, X1 + 3, X1 + 6, X1 + 9, 0.0, t_max);
  if (kind == PairKind::edge_edge)
    return contact::edge_edge_time_of_impact(X0, X0 + 3, X0 + 6, X0 + 9, X1, X1 + 3, X1 + 6, X1 + 9, 0.0, t_max);
  return contact::point_plane_time_of_impact(X0, X1, plane_point, plane_normal, 0.0, t_max);
}

}  // namespace dipc
