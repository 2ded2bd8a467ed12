// PrescribedMotion: where a point given at X (its position at t = 0) is at time t, for
// Dirichlet nodes, kinematic bodies and triangle-mesh obstacles.
#pragma once
#include <array>
#include <vector>

namespace dipc {

struct PrescribedMotion {
  // Affine: x(t) = X + t (A X + velocity), a uniform deformation rate (stretch/shear tests).
  // Path: x(t) = X + d(t), d piecewise linear through the keyframes (t_k, d_k), held at the
  // last keyframe's d after it; the first keyframe is (0, 0), so x(0) = X.
  enum class Kind { Fixed, Velocity, Rotation, Affine, Path };
  Kind kind = Kind::Fixed;
  std::array<double, 3> velocity{0, 0, 0};
  std::array<double, 9> rate{0, 0, 0, 0, 0, 0, 0, 0, 0};  // A, row-major (Affine only)
  std::array<double, 3> axis{0, 0, 1};                    // unit vector
  std::array<double, 3> center{0, 0, 0};
  double angular_velocity = 0;              // rad/s, right-handed about axis
  std::vector<std::array<double, 4>> path;  // Path: (t, dx, dy, dz), t strictly increasing from 0
  std::array<double, 3> position(const std::array<double, 3>& X, double t) const;
  std::array<double, 3> velocity_at(const std::array<double, 3>& X, double t) const;
};

}  // namespace dipc
