// check_closed_surface and signed_enclosed_volume (see closed_surface.hpp).
#include "mesh/closed_surface.hpp"

#include <algorithm>
#include <sstream>
#include <tuple>

#include "math/vector3.hpp"
#include "mesh/mesh_error.hpp"

namespace dipc {

namespace {

struct HalfEdge {
  std::int64_t lo, hi;  // vertex ids, lo < hi
  std::int64_t triangle;
  bool forward;  // the triangle runs lo -> hi
  bool operator<(const HalfEdge& o) const { return std::tie(lo, hi, triangle) < std::tie(o.lo, o.hi, o.triangle); }
};

std::string point(const Vec3& p) {
  std::ostringstream s;
  s.precision(17);
  s << "(" << p[0] << " " << p[1] << " " << p[2] << ")";
  return s.str();
}

}  // namespace

void check_closed_surface(const TriangleSurface& surface) {
  std::vector<HalfEdge> edges;
  edges.reserve(3 * surface.triangles.size());
  for (std::size_t t = 0; t < surface.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const std::int64_t a = surface.triangles[t][k], b = surface.triangles[t][(k + 1) % 3];
      edges.push_back({std::min(a, b), std::max(a, b), static_cast<std::int64_t>(t), a < b});
    }
  std::sort(edges.begin(), edges.end());
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i;
    while (j < edges.size() && edges[j].lo == edges[i].lo && edges[j].hi == edges[i].hi) ++j;
    auto edge = [&] {  // built for a message only: formatting every edge would be slow
      return "edge " + point(surface.vertices[edges[i].lo]) + "-" + point(surface.vertices[edges[i].hi]);
    };
    auto at = [&](std::size_t e) { return describe_triangle(surface, edges[e].triangle); };
    if (j - i == 1)
      throw MeshError(surface.source + ": the surface is not closed: " + edge() + " belongs to one triangle only (" +
                      at(i) + "); a solid needs a closed surface");
    if (j - i > 2) {
      std::string where;
      for (std::size_t e = i; e < j; ++e) where += (e > i ? ", " : "") + at(e);
      throw MeshError(surface.source + ": the surface is not manifold: " + edge() + " is shared by " +
                      std::to_string(j - i) + " triangles (" + where + ")");
    }
    if (edges[i].forward == edges[i + 1].forward)
      throw MeshError(surface.source + ": the surface is not consistently oriented: triangles " + at(i) + " and " +
                      at(i + 1) + " run along their shared " + edge() +
                      " in the same direction (one of them is flipped)");
    i = j;
  }
}

double signed_enclosed_volume(const TriangleSurface& surface) {
  // Relative to the first vertex (the sum does not depend on the origin for a closed
  // surface), which keeps the products small for a model far from the coordinate origin.
  const Vec3 o = surface.vertices.empty() ? Vec3{0, 0, 0} : surface.vertices[0];
  auto rel = [&](std::int64_t v) {
    const Vec3& p = surface.vertices[v];
    return Vec3{p[0] - o[0], p[1] - o[1], p[2] - o[2]};
  };
  double v = 0;
  for (const Triangle& t : surface.triangles) {
    const Vec3 a = rel(t[0]), b = rel(t[1]), c = rel(t[2]);
    Vec3 bxc;
    cross3(b.data(), c.data(), bxc.data());
    v += dot3(a.data(), bxc.data());
  }
  return v / 6;
}

}  // namespace dipc
