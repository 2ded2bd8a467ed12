// Geometry helpers shared by the boundary-face and surface-mesh tests: vector algebra on
// Vec3, area vectors of quads and triangles, and test meshes with a cavity or glued bodies.
#pragma once
#include <array>
#include <cmath>
#include <cstdint>

#include "mesh/box_generator.hpp"
#include "mesh/hex_mesh.hpp"

namespace dipc::test {

inline Vec3 sub(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
inline Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
inline double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline double norm(const Vec3& a) { return std::sqrt(dot(a, a)); }

// Vector area ½ (x2 − x0) × (x3 − x1) of the quad x0 x1 x2 x3: its length is the area of a
// planar quad and it points along the right-hand-rule normal of the corner order.
inline Vec3 quad_area_vector(const HexMesh& mesh, const std::array<std::int64_t, 4>& q) {
  const Vec3 c = cross(sub(mesh.nodes[q[2]], mesh.nodes[q[0]]), sub(mesh.nodes[q[3]], mesh.nodes[q[1]]));
  return {0.5 * c[0], 0.5 * c[1], 0.5 * c[2]};
}

inline Vec3 triangle_area_vector(const Vec3& x0, const Vec3& x1, const Vec3& x2) {
  const Vec3 c = cross(sub(x1, x0), sub(x2, x0));
  return {0.5 * c[0], 0.5 * c[1], 0.5 * c[2]};
}

inline Vec3 centroid(const HexMesh& mesh, const std::int64_t* ids, int n) {
  Vec3 c{0, 0, 0};
  for (int i = 0; i < n; ++i)
    for (int d = 0; d < 3; ++d) c[d] += mesh.nodes[ids[i]][d] / n;
  return c;
}

// A unit-spaced n x n x n box with its centre element removed: an outer surface and an
// internal cubic cavity (every node is still used by some element).
inline HexMesh box_with_cavity(int n) {
  HexMesh mesh = generate_box({1.0 * n, 1.0 * n, 1.0 * n}, {n, n, n}, {0, 0, 0}, 0, "block");
  const int c = n / 2;
  const auto centre = static_cast<std::ptrdiff_t>(c + n * (c + n * c));
  mesh.hexes.erase(mesh.hexes.begin() + centre);
  mesh.body.erase(mesh.body.begin() + centre);
  return mesh;
}

}  // namespace dipc::test
