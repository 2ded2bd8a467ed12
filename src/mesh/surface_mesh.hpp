// The boundary surface of a whole HexMesh as a triangle mesh (boundary quads split in two),
// with its unique edges and vertices, in one canonical order that depends only on the input
// mesh. Rank 0 builds it before partitioning; positions in these arrays are the global ids
// of the contact primitives (partition/contact_surface.hpp), so they are the same for every
// number of ranks.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "mesh/boundary_faces.hpp"
#include "mesh/hex_mesh.hpp"

namespace dipc {

// A boundary quad is split along the diagonal through its corner with the smallest node
// id. With input node ids (never partition-ordered ones) the rule gives the same triangles
// wherever the quad is split, on rank 0 or on the rank that owns the element. Returns the
// corner index 0..3 of `ids` (the quad's node ids in hex_face_nodes order).
inline int quad_split_corner(const std::int64_t ids[4]) {
  int m = 0;
  for (int i = 1; i < 4; ++i) {
    if (ids[i] < ids[m]) m = i;
  }
  return m;
}

// Quad corners of triangle k (0 or 1) of a quad split at corner m: (m, m+1, m+2) and
// (m, m+2, m+3), indices mod 4. Both keep the quad's counter-clockwise order, so the
// triangles face outward like the quad.
inline std::array<int, 3> quad_triangle_corners(int split_corner, int k) {
  const int m = split_corner;
  return k == 0 ? std::array<int, 3>{m, (m + 1) % 4, (m + 2) % 4} : std::array<int, 3>{m, (m + 2) % 4, (m + 3) % 4};
}

struct SurfaceMesh {
  // extract_boundary_faces(mesh): sorted by element, then face.
  std::vector<BoundaryFace> quads;
  // Triangle 2q + k is triangle k of quad q (quad_triangle_corners), as input node ids,
  // counter-clockwise seen from outside the body.
  std::vector<std::array<std::int64_t, 3>> triangles;
  std::vector<int> triangle_body;  // body of the quad's element
  // Index into `edges` of side i of each triangle, the side from corner i to corner i+1.
  std::vector<std::array<std::int64_t, 3>> triangle_edges;
  // The unique triangle sides (quad diagonals included) as (smaller id, larger id), sorted.
  std::vector<std::array<std::int64_t, 2>> edges;
  // The unique triangle corners, sorted input node ids.
  std::vector<std::int64_t> vertices;
  // Body of the lowest-numbered triangle that uses the edge / vertex. Only bodies meshed
  // with shared nodes can give one edge triangles of two bodies; the rule keeps the answer
  // deterministic then.
  std::vector<int> edge_body;
  std::vector<int> vertex_body;
};

// Extracts and triangulates the boundary of `mesh` (one body id per element required).
// Throws MeshError as extract_boundary_faces does, or when body ids are missing.
SurfaceMesh build_surface_mesh(const HexMesh& mesh);

// Index of `node` in surface.vertices (binary search), or -1 when it is no surface vertex.
std::int64_t surface_vertex_index(const SurfaceMesh& surface, std::int64_t node);

}  // namespace dipc
