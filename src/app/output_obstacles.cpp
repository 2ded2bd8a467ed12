#include "app/output_obstacles.hpp"

#include <cmath>
#include <string>

#include "math/vector3.hpp"

namespace dipc {

namespace {

using V3 = std::array<double, 3>;

V3 cross(const V3& a, const V3& b) {
  V3 c;
  cross3(a.data(), b.data(), c.data());
  return c;
}

V3 normalised(const V3& a) {
  const double n = std::sqrt(squared_norm3(a.data()));
  return {a[0] / n, a[1] / n, a[2] / n};
}

}  // namespace

std::vector<OutputObstacle> output_obstacles(const ContactParameters& contact, const Bounds& bounds) {
  std::vector<OutputObstacle> out;
  const V3 centre{0.5 * (bounds[0] + bounds[3]), 0.5 * (bounds[1] + bounds[4]), 0.5 * (bounds[2] + bounds[5])};
  double d2 = 0;
  for (int c = 0; c < 3; ++c) d2 += (bounds[3 + c] - bounds[c]) * (bounds[3 + c] - bounds[c]);
  // A degenerate box (one node) would make a point: fall back on a unit patch.
  const double D = d2 > 0 ? std::sqrt(d2) : 1.0;
  for (std::size_t i = 0; i < contact.planes.size(); ++i) {
    const V3 n = normalised(contact.planes[i].normal);
    const V3& p = contact.planes[i].point;
    double height = 0;
    for (int c = 0; c < 3; ++c) height += (centre[c] - p[c]) * n[c];
    V3 c0;
    for (int c = 0; c < 3; ++c) c0[c] = centre[c] - height * n[c];
    // t1 ⟂ n from the coordinate axis least aligned with n; t2 = n × t1, so t1 × t2 = n.
    int axis = 0;
    for (int c = 1; c < 3; ++c)
      if (std::abs(n[c]) < std::abs(n[axis])) axis = c;
    V3 e{0, 0, 0};
    e[axis] = 1;
    const V3 t1 = normalised(cross(n, e)), t2 = cross(n, t1);
    OutputObstacle o;
    o.name = "plane" + std::to_string(i);
    o.kind = "plane";
    o.nodes_per_cell = 4;
    const double corner[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
    for (const auto& s : corner)
      for (int c = 0; c < 3; ++c) o.rest.push_back(c0[c] + D * (s[0] * t1[c] + s[1] * t2[c]));
    o.cells = {0, 1, 2, 3};
    out.push_back(std::move(o));
  }
  for (const ContactParameters::Obstacle& m : contact.obstacles) {
    OutputObstacle o;
    o.name = m.name;
    o.kind = "triangle_mesh";
    o.nodes_per_cell = 3;
    for (const auto& X : m.rest) o.rest.insert(o.rest.end(), X.begin(), X.end());
    for (const auto& t : m.triangles) o.cells.insert(o.cells.end(), t.begin(), t.end());
    o.moving = m.motion.kind != PrescribedMotion::Kind::Fixed;
    out.push_back(std::move(o));
  }
  return out;
}

std::vector<std::vector<double>> obstacle_displacements(const ContactParameters& contact, double t) {
  std::vector<std::vector<double>> out;
  for (const ContactParameters::Obstacle& m : contact.obstacles) {
    if (m.motion.kind == PrescribedMotion::Kind::Fixed) continue;
    std::vector<double> u;
    u.reserve(3 * m.rest.size());
    for (const auto& X : m.rest) {
      const V3 x = m.motion.position(X, t);
      for (int c = 0; c < 3; ++c) u.push_back(x[c] - X[c]);
    }
    out.push_back(std::move(u));
  }
  return out;
}

}  // namespace dipc
