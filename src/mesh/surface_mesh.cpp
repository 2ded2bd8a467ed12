// build_surface_mesh (see surface_mesh.hpp): quads -> triangles, then the unique edges by
// sorting every triangle side once (O(T log T) in the number of surface triangles T, which
// is O(elements^(2/3)) for solid bodies), then the unique vertices.
#include "mesh/surface_mesh.hpp"

#include <algorithm>
#include <string>

#include "mesh/mesh_error.hpp"

namespace dipc {
namespace {

// One triangle side: its end nodes (smaller first) and 3 * triangle + side.
struct SideRecord {
  std::int64_t a;
  std::int64_t b;
  std::int64_t side_code;
  bool operator<(const SideRecord& o) const {
    if (a != o.a) return a < o.a;
    if (b != o.b) return b < o.b;
    return side_code < o.side_code;
  }
};

void triangulate_quads(const HexMesh& mesh, SurfaceMesh& s) {
  s.triangles.resize(2 * s.quads.size());
  s.triangle_body.resize(2 * s.quads.size());
  for (std::size_t q = 0; q < s.quads.size(); ++q) {
    const Hex& hex = mesh.hexes[static_cast<std::size_t>(s.quads[q].element)];
    const std::array<int, 4> corners = hex_face_nodes(s.quads[q].face);
    std::int64_t ids[4];
    for (int i = 0; i < 4; ++i) ids[i] = hex[corners[i]];
    const int m = quad_split_corner(ids);
    for (int k = 0; k < 2; ++k) {
      const std::array<int, 3> c = quad_triangle_corners(m, k);
      s.triangles[2 * q + k] = {ids[c[0]], ids[c[1]], ids[c[2]]};
      s.triangle_body[2 * q + k] = mesh.body[static_cast<std::size_t>(s.quads[q].element)];
    }
  }
}

void collect_edges(SurfaceMesh& s) {
  std::vector<SideRecord> sides;
  sides.reserve(3 * s.triangles.size());
  for (std::size_t t = 0; t < s.triangles.size(); ++t) {
    for (int i = 0; i < 3; ++i) {
      const std::int64_t u = s.triangles[t][i];
      const std::int64_t v = s.triangles[t][(i + 1) % 3];
      sides.push_back({std::min(u, v), std::max(u, v), static_cast<std::int64_t>(3 * t + i)});
    }
  }
  std::sort(sides.begin(), sides.end());
  s.triangle_edges.resize(s.triangles.size());
  for (std::size_t i = 0; i < sides.size(); ++i) {
    const bool new_edge = i == 0 || sides[i].a != sides[i - 1].a || sides[i].b != sides[i - 1].b;
    if (new_edge) {
      s.edges.push_back({sides[i].a, sides[i].b});
      // Sides of one edge are sorted by triangle, so the first is the lowest-numbered one.
      s.edge_body.push_back(s.triangle_body[static_cast<std::size_t>(sides[i].side_code / 3)]);
    }
    const std::int64_t edge = static_cast<std::int64_t>(s.edges.size()) - 1;
    s.triangle_edges[static_cast<std::size_t>(sides[i].side_code / 3)][sides[i].side_code % 3] = edge;
  }
}

void collect_vertices(SurfaceMesh& s) {
  for (const auto& triangle : s.triangles) {
    s.vertices.insert(s.vertices.end(), triangle.begin(), triangle.end());
  }
  std::sort(s.vertices.begin(), s.vertices.end());
  s.vertices.erase(std::unique(s.vertices.begin(), s.vertices.end()), s.vertices.end());
  s.vertex_body.assign(s.vertices.size(), -1);
  for (std::size_t t = 0; t < s.triangles.size(); ++t) {
    for (std::int64_t node : s.triangles[t]) {
      int& body = s.vertex_body[static_cast<std::size_t>(surface_vertex_index(s, node))];
      if (body < 0) body = s.triangle_body[t];
    }
  }
}

}  // namespace

SurfaceMesh build_surface_mesh(const HexMesh& mesh) {
  if (mesh.body.size() != mesh.num_elements()) {
    throw MeshError("build_surface_mesh: the mesh has " + std::to_string(mesh.body.size()) + " body ids for " +
                    std::to_string(mesh.num_elements()) + " elements");
  }
  SurfaceMesh s;
  s.quads = extract_boundary_faces(mesh);
  triangulate_quads(mesh, s);
  collect_edges(s);
  collect_vertices(s);
  return s;
}

std::int64_t surface_vertex_index(const SurfaceMesh& surface, std::int64_t node) {
  const auto it = std::lower_bound(surface.vertices.begin(), surface.vertices.end(), node);
  if (it == surface.vertices.end() || *it != node) return -1;
  return it - surface.vertices.begin();
}

}  // namespace dipc
