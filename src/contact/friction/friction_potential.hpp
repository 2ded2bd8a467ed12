// The lagged IPC friction potential of one contact pair, its gradient and Hessian (Li et al.
// 2020, "Incremental Potential Contact", ACM TOG 39(4), §5 and the supplement), as
// host/device point functions. With the lagged data of lagged_friction.hpp,
//   u   = P^T Gamma (x - x_n)                      tangential relative displacement (2)
//   D   = mu lambda f0(||u||)                      (f0: friction_mollifier.hpp)
//   dD  = mu lambda f1(y)/y  Gamma^T P u,  y = ||u||
//   d2D = Gamma^T P M P^T Gamma,  M = mu lambda [f1(y)/y I + (f1'(y) y - f1(y))/y^3 u u^T]
// The Hessian's 2x2 inner matrix M has eigenvalues mu lambda f1(y)/y (orthogonal to u) and
// mu lambda f1'(y) (along u); both are >= 0 for this mollifier in exact arithmetic, but the
// along-u one is computed as a difference that rounds to slightly negative values in the
// sliding regime (where it is exactly 0), so the projected Hessian clamps M's eigenvalues
// (symmetric_2x2_psd.hpp), as IPC does; Gamma^T P M P^T Gamma is then PSD by congruence.
//
// A Newton model built on that Hessian overshoots where a pair's slip reverses: in the sliding
// regime the along-u curvature is 0, so a pair that should come to rest is sent across the
// cone's apex to slide the other way, and the line search cuts the step of every node for it
// (issue 29: the heavy steps of the contact family). For such pairs the form may use the
// isotropic majorizer instead (friction_hessian with FrictionModel::majorizer).
//
// The 12-dof functions serve point-triangle [p, t0, t1, t2] and edge-edge
// [ea0, ea1, eb0, eb1] pairs alike (only Gamma's weights differ); the 3-dof overloads are
// the point-plane pairs. Gradients and Hessians are written (not accumulated); Hessians are
// row-major (H[n*i + j]).
#pragma once
#include <cmath>

#include "contact/friction/friction_mollifier.hpp"
#include "contact/friction/lagged_friction.hpp"
#include "contact/friction/relative_velocity.hpp"
#include "contact/friction/symmetric_2x2_psd.hpp"
#include "math/host_device.hpp"

namespace dipc::contact {

namespace friction_detail {

// u = P^T r
DIPC_HD void project_to_tangent(const double P[6], const double r[3], double u[2]) {
  u[0] = P[0] * r[0] + P[2] * r[1] + P[4] * r[2];
  u[1] = P[1] * r[0] + P[3] * r[1] + P[5] * r[2];
}

// A = P M P^T (3x3 row-major) for the symmetric 2x2 row-major M. The upper triangle is
// mirrored so A (and the pair Hessian built from it) is exactly symmetric, as CG requires.
DIPC_HD void lift_from_tangent(const double P[6], const double M[4], double A[9]) {
  for (int a = 0; a < 3; ++a) {
    const double pm0 = P[2 * a] * M[0] + P[2 * a + 1] * M[1];
    const double pm1 = P[2 * a] * M[1] + P[2 * a + 1] * M[3];
    for (int b = a; b < 3; ++b) A[3 * a + b] = A[3 * b + a] = pm0 * P[2 * b] + pm1 * P[2 * b + 1];
  }
}

// The 3-vector mu lambda f1(y)/y P u: the gradient of D with respect to the relative
// position Gamma x, i.e. minus the friction force on the first closest point.
DIPC_HD void tangential_force(const double P[6], const double u[2], double eps_u, double mu_lambda, double t[3]) {
  const double y = sqrt(u[0] * u[0] + u[1] * u[1]);
  const double s = mu_lambda * friction_f1_over_y(y, eps_u);
  for (int a = 0; a < 3; ++a) t[a] = s * (P[2 * a] * u[0] + P[2 * a + 1] * u[1]);
}

}  // namespace friction_detail

// M = mu lambda [f1(y)/y I + (f1'(y) y - f1(y))/y^3 u u^T], then projected onto the PSD
// cone if `project`. At y = 0 the u u^T term is O(y) -> 0 and M = mu lambda (2/eps_u) I.
DIPC_HD void friction_inner_hessian(const double u[2], double eps_u, double mu_lambda, bool project, double M[4]) {
  const double y = sqrt(u[0] * u[0] + u[1] * u[1]);
  const double diag = mu_lambda * friction_f1_over_y(y, eps_u);
  M[0] = M[3] = diag;
  M[1] = M[2] = 0.0;
  if (y > 0.0) {
    const double c = mu_lambda * friction_f1_derivative_term(y, eps_u);
    M[0] += c * u[0] * u[0];
    M[1] += c * u[0] * u[1];
    M[2] = M[1];
    M[3] += c * u[1] * u[1];
  }
  if (project) project_symmetric_2x2_to_psd(M);
}

// The inner Hessian of D's isotropic majorizer at u0, M = mu lambda f1(y0)/y0 I. Since f1(y)/y
// does not increase with y (f0(sqrt(s)) is concave in s, friction_mollifier.hpp), for every u
//   D(u) <= D(u0) + mu lambda f1(y0)/(2 y0) (||u||^2 - y0^2),
// the bound behind iteratively reweighted least squares (Weiszfeld's algorithm): a quadratic
// that touches D at u0 with D's gradient. Along u it is stiffer than D (f1/y against f1'), so
// the model's minimiser of D alone is the apex u = 0, never beyond it. PSD by construction.
DIPC_HD void friction_majorizer_inner_hessian(const double u[2], double eps_u, double mu_lambda, double M[4]) {
  const double y = sqrt(u[0] * u[0] + u[1] * u[1]);
  M[0] = M[3] = mu_lambda * friction_f1_over_y(y, eps_u);
  M[1] = M[2] = 0.0;
}

// Whether the move u0 -> u1 reverses a sliding pair's slip: sliding at both ends (||u|| >= eps_u)
// in directions more than 90 degrees apart, so the segment passes the stick disc or its side.
DIPC_HD bool slip_reverses(const double u0[2], const double u1[2], double eps_u) {
  const double y0 = sqrt(u0[0] * u0[0] + u0[1] * u0[1]), y1 = sqrt(u1[0] * u1[0] + u1[1] * u1[1]);
  return y0 >= eps_u && y1 >= eps_u && u0[0] * u1[0] + u0[1] * u1[1] < 0.0;
}

// Which inner Hessian a pair Hessian is built from.
enum class FrictionModel {
  exact,       // D's own (may be slightly indefinite by rounding; for tests)
  projected,   // D's own, eigenvalues clamped at 0: what Newton uses
  majorizer,   // the isotropic majorizer (friction_majorizer_inner_hessian)
};

DIPC_HD void friction_model_inner_hessian(const double u[2], double eps_u, double mu_lambda, FrictionModel model,
                                          double M[4]) {
  if (model == FrictionModel::majorizer)
    friction_majorizer_inner_hessian(u, eps_u, mu_lambda, M);
  else
    friction_inner_hessian(u, eps_u, mu_lambda, model == FrictionModel::projected, M);
}

// ---- point-triangle and edge-edge pairs (12 dofs) ----

// u = P^T Gamma (x - x_n)
DIPC_HD void tangential_displacement(const double x12[12], const double xn12[12], const LaggedPairFriction& f,
                                     double u[2]) {
  double dx[12], r[3];
  for (int i = 0; i < 12; ++i) dx[i] = x12[i] - xn12[i];
  apply_relative_velocity(f.weights, dx, r);
  friction_detail::project_to_tangent(f.basis, r, u);
}

DIPC_HD double friction_energy(const double x12[12], const double xn12[12], const LaggedPairFriction& f) {
  double u[2];
  tangential_displacement(x12, xn12, f, u);
  return f.mu * f.normal_force * friction_f0(sqrt(u[0] * u[0] + u[1] * u[1]), f.eps_u);
}

DIPC_HD void friction_gradient(const double x12[12], const double xn12[12], const LaggedPairFriction& f,
                               double g12[12]) {
  double u[2], t[3];
  tangential_displacement(x12, xn12, f, u);
  friction_detail::tangential_force(f.basis, u, f.eps_u, f.mu * f.normal_force, t);
  apply_relative_velocity_transpose(f.weights, t, g12);
}

// The Hessian of the chosen model (FrictionModel), for a caller that picks it per pair:
// H = Gamma^T A Gamma with Gamma = [w_i I], H_(3i+a, 3j+b) = w_i w_j A_ab. The majorizer's is
// Gamma^T P (mu lambda f1(y)/y I) P^T Gamma (for a pair whose slip the last Newton step reversed).
DIPC_HD void friction_hessian(const double x12[12], const double xn12[12], const LaggedPairFriction& f,
                              FrictionModel model, double H144[144]) {
  double u[2], M[4], A[9];
  tangential_displacement(x12, xn12, f, u);
  friction_model_inner_hessian(u, f.eps_u, f.mu * f.normal_force, model, M);
  friction_detail::lift_from_tangent(f.basis, M, A);
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) {
      const double wij = f.weights[i] * f.weights[j];
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) H144[12 * (3 * i + a) + 3 * j + b] = wij * A[3 * a + b];
    }
}

// PSD-projected Hessian (what Newton uses).
DIPC_HD void friction_hessian(const double x12[12], const double xn12[12], const LaggedPairFriction& f,
                              double H144[144]) {
  friction_hessian(x12, xn12, f, FrictionModel::projected, H144);
}

// The exact Hessian of friction_energy (may be slightly indefinite by rounding; for tests).
DIPC_HD void friction_hessian_unprojected(const double x12[12], const double xn12[12], const LaggedPairFriction& f,
                                          double H144[144]) {
  friction_hessian(x12, xn12, f, FrictionModel::exact, H144);
}

// ---- point-plane pairs (3 dofs, Gamma = I) ----

DIPC_HD void tangential_displacement(const double x3[3], const double xn3[3], const LaggedPointPlaneFriction& f,
                                     double u[2]) {
  const double dx[3] = {x3[0] - xn3[0], x3[1] - xn3[1], x3[2] - xn3[2]};
  friction_detail::project_to_tangent(f.basis, dx, u);
}

DIPC_HD double friction_energy(const double x3[3], const double xn3[3], const LaggedPointPlaneFriction& f) {
  double u[2];
  tangential_displacement(x3, xn3, f, u);
  return f.mu * f.normal_force * friction_f0(sqrt(u[0] * u[0] + u[1] * u[1]), f.eps_u);
}

DIPC_HD void friction_gradient(const double x3[3], const double xn3[3], const LaggedPointPlaneFriction& f,
                               double g3[3]) {
  double u[2];
  tangential_displacement(x3, xn3, f, u);
  friction_detail::tangential_force(f.basis, u, f.eps_u, f.mu * f.normal_force, g3);
}

DIPC_HD void friction_hessian(const double x3[3], const double xn3[3], const LaggedPointPlaneFriction& f,
                              FrictionModel model, double H9[9]) {
  double u[2], M[4];
  tangential_displacement(x3, xn3, f, u);
  friction_model_inner_hessian(u, f.eps_u, f.mu * f.normal_force, model, M);
  friction_detail::lift_from_tangent(f.basis, M, H9);
}

DIPC_HD void friction_hessian(const double x3[3], const double xn3[3], const LaggedPointPlaneFriction& f,
                              double H9[9]) {
  friction_hessian(x3, xn3, f, FrictionModel::projected, H9);
}

DIPC_HD void friction_hessian_unprojected(const double x3[3], const double xn3[3], const LaggedPointPlaneFriction& f,
                                          double H9[9]) {
  friction_hessian(x3, xn3, f, FrictionModel::exact, H9);
}

}  // namespace dipc::contact
