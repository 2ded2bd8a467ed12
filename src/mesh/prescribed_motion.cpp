// Positions and velocities of prescribed points: fixed, constant velocity, rigid rotation
// about an axis (Rodrigues' rotation formula), an affine deformation rate, or a piecewise
// linear path of translations.
#include "mesh/prescribed_motion.hpp"

#include <algorithm>
#include <cmath>

#include "math/vector3.hpp"

namespace dipc {

namespace {
using V3 = std::array<double, 3>;
V3 cross(const V3& a, const V3& b) {
  V3 c;
  cross3(a.data(), b.data(), c.data());
  return c;
}
double dot(const V3& a, const V3& b) { return dot3(a.data(), b.data()); }

// The path's keyframe segment [k, k+1] holding t (the last one when t is beyond it); the
// parser guarantees at least two keyframes.
std::size_t path_segment(const std::vector<std::array<double, 4>>& path, double t) {
  std::size_t k = 0;
  while (k + 2 < path.size() && t >= path[k + 1][0]) ++k;
  return k;
}
}  // namespace

std::array<double, 3> PrescribedMotion::position(const std::array<double, 3>& X, double t) const {
  switch (kind) {
    case Kind::Fixed: return X;
    case Kind::Velocity: return {X[0] + velocity[0] * t, X[1] + velocity[1] * t, X[2] + velocity[2] * t};
    case Kind::Affine: {
      const V3 v = velocity_at(X, t);
      return {X[0] + t * v[0], X[1] + t * v[1], X[2] + t * v[2]};
    }
    case Kind::Path: {
      if (path.size() < 2) return X;
      const std::size_t k = path_segment(path, t);
      const auto& a = path[k];
      const auto& b = path[k + 1];
      // Clamped to the keyframes: the path holds its last translation after its end.
      const double s = std::min(1.0, std::max(0.0, (t - a[0]) / (b[0] - a[0])));
      return {X[0] + a[1] + s * (b[1] - a[1]), X[1] + a[2] + s * (b[2] - a[2]), X[2] + a[3] + s * (b[3] - a[3])};
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
    case Kind::Fixed: return {0, 0, 0};
    case Kind::Velocity: return velocity;
    case Kind::Affine: {
      V3 v = velocity;
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) v[i] += rate[3 * i + j] * X[j];
      return v;
    }
    case Kind::Path: {
      // The slope of the segment that starts at t (right derivative), zero after the end.
      if (path.size() < 2 || t >= path.back()[0]) return {0, 0, 0};
      const auto& a = path[path_segment(path, t)];
      const auto& b = path[path_segment(path, t) + 1];
      const double dt = b[0] - a[0];
      return {(b[1] - a[1]) / dt, (b[2] - a[2]) / dt, (b[3] - a[3]) / dt};
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
