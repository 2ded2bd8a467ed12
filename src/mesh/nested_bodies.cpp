#include "mesh/nested_bodies.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "math/aabb.hpp"
#include "math/vector3.hpp"
#include "mesh/mesh_checks.hpp"
#include "mesh/mesh_error.hpp"
#include "mesh/surface_mesh.hpp"

namespace dipc {

namespace {

// Vertices tried per pair of bodies before the pair counts as not nested: only vertices that
// lie on the other surface leave the answer open, and a body rarely has this many spread over
// its surface that all do.
constexpr int kVerticesTried = 8;

// Whether a lies inside b grown by `tolerance` on every side.
bool box_within(const Aabb& a, const Aabb& b, double tolerance) {
  for (int c = 0; c < 3; ++c)
    if (a.lo[c] < b.lo[c] - tolerance || a.hi[c] > b.hi[c] + tolerance) return false;
  return true;
}

double box_diagonal(const Aabb& b) {
  double d[3];
  subtract3(b.hi, b.lo, d);
  return std::sqrt(squared_norm3(d));
}

}  // namespace

double winding_number(const HexMesh& mesh, const std::vector<std::array<std::int64_t, 3>>& triangles,
                      const Vec3& point) {
  constexpr double kPi = 3.14159265358979323846;
  double sum = 0;
  for (const auto& t : triangles) {
    Vec3 r[3];
    for (int k = 0; k < 3; ++k)
      for (int c = 0; c < 3; ++c) r[k][c] = mesh.nodes[static_cast<std::size_t>(t[k])][c] - point[c];
    sum += solid_angle3(r[0].data(), r[1].data(), r[2].data());
  }
  return sum / (4 * kPi);
}

NestedBodies find_nested_bodies(const HexMesh& mesh) {
  if (mesh.body.empty()) return {};
  const int num_bodies = *std::max_element(mesh.body.begin(), mesh.body.end()) + 1;
  if (num_bodies < 2) return {};
  const SurfaceMesh surface = build_surface_mesh(mesh);
  std::vector<std::vector<std::array<std::int64_t, 3>>> triangles(num_bodies);
  for (std::size_t t = 0; t < surface.triangles.size(); ++t)
    triangles[surface.triangle_body[t]].push_back(surface.triangles[t]);
  std::vector<std::vector<std::int64_t>> vertices(num_bodies);
  std::vector<Aabb> box(num_bodies, aabb_empty());
  for (std::size_t v = 0; v < surface.vertices.size(); ++v) {
    const int b = surface.vertex_body[v];
    vertices[b].push_back(surface.vertices[v]);
    const Vec3& X = mesh.nodes[static_cast<std::size_t>(surface.vertices[v])];
    aabb_add_point(&box[b], X.data());
  }
  for (int inner = 0; inner < num_bodies; ++inner)
    for (int outer = 0; outer < num_bodies; ++outer) {
      if (inner == outer || vertices[inner].empty() || triangles[outer].empty()) continue;
      // A body inside another lies inside its bounding box (up to round-off of the placement).
      if (!box_within(box[inner], box[outer], 1e-9 * box_diagonal(box[outer]))) continue;
      const std::vector<std::int64_t>& candidates = vertices[inner];
      const std::size_t tries = std::min<std::size_t>(kVerticesTried, candidates.size());
      for (std::size_t k = 0; k < tries; ++k) {
        const std::int64_t node = candidates[k * candidates.size() / tries];  // spread over the body
        const double w = winding_number(mesh, triangles[outer], mesh.nodes[static_cast<std::size_t>(node)]);
        if (w > 0.75) return {inner, outer, node};
        if (w < 0.25) break;
      }
    }
  return {};
}

void check_no_nested_bodies(const HexMesh& mesh, const std::vector<std::string>& body_names,
                            const std::string& source) {
  const NestedBodies nested = find_nested_bodies(mesh);
  if (nested.inner < 0) return;
  auto name = [&](int b) {
    return b < static_cast<int>(body_names.size()) ? "\"" + body_names[b] + "\"" : std::to_string(b);
  };
  throw MeshError(source + ": body " + name(nested.inner) + " lies inside body " + name(nested.outer) + " (its node " +
                  std::to_string(nested.node) + " is enclosed by the surface of " + name(nested.outer) +
                  "); bodies in contact must start apart");
}

}  // namespace dipc
