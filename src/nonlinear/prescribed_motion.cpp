// Positions and velocities of Dirichlet nodes: fixed, constant velocity, or rigid rotation
// about an axis (Rodrigues' rotation formula), or an affine deformation rate.
#include <cmath>

#include "nonlinear/problem.hpp"

namespace dipc {

namespace {
using V3 = std::array<double, 3>;
V3 cross(const V3& a, const V3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double dot(const V3& a, const V3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
}  // namespace

std::array<double, 3> PrescribedMotion::position(const std::array<double, 3>& X, double t) const {
  switch (kind) {
    case Kind::Fixed:
      return X;
    case Kind::Velocity:
      return {X[0] + velocity[0] * t, X[1] + velocity[1] * t, X[2] + velocity[2] * t};
    case Kind::Affine: {
      const V3 v = velocity_at(X, t);
      return {X[0] + t * v[0], X[1] + t * v[1], X[2] + t * v[2]};
    }
    case Kind::Rotation: {
      // R r = r cosθ + (k × r) sinθ + k (k·r)(1 − cosθ), r = X − c, θ = ω t.
      const V3 r{X[0] - center[0], X[1] - center[1], X[2] - center[2]};
      const double th = angular_velocity * t, c = std::cos(th), s = std::sin(th);
      const V3 kxr = cross(axis, r);
      const double kr = dot(axis, r);
      V3 x;
      for (int i = 0; i < 3; ++i) x[i] = center[i] + r[i] * c + kxr[i] * s + axis[i] * kr * (1 - c);
      return x;
    }
  }
  return X;
}

std::array<double, 3> PrescribedMotion::velocity_at(const std::array<double, 3>& X, double t) const {
  switch (kind) {
    case Kind::Fixed:
      return {0, 0, 0};
    case Kind::Velocity:
      return velocity;
    case Kind::Affine: {
      V3 v = velocity;
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) v[i] += rate[3 * i + j] * X[j];
      return v;
    }
    case Kind::Rotation: {
      const V3 x = position(X, t);
      const V3 r{x[0] - center[0], x[1] - center[1], x[2] - center[2]};
      const V3 w{angular_velocity * axis[0], angular_velocity * axis[1], angular_velocity * axis[2]};
      return cross(w, r);
    }
  }
  return {0, 0, 0};
}

}  // namespace dipc
