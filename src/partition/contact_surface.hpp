// ContactSurface: the contact primitives (surface triangles, edges, vertices) that this rank
// OWNS, built from a DistributedMesh. Every primitive of the whole mesh's surface is owned by
// exactly one rank (rules in partition/surface_owners.hpp: a triangle by the rank of its
// element, an edge or vertex by the lowest rank that owns a triangle using it), so summing
// per-primitive terms over owned primitives counts each once. Triangles are the boundary
// quads split along the diagonal through their corner with the smallest INPUT node id
// (mesh/surface_mesh.hpp), counter-clockwise seen from outside, so (x1 - x0) × (x2 - x0)
// is the outward normal. Global ids index the canonical whole-mesh surface: dense, unique
// over ranks and independent of the number of ranks. Node ids are local node ids of the
// DistributedMesh (owned or ghost nodes).
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "partition/distributed_mesh.hpp"

namespace dipc {

struct ContactSurface {
  std::vector<std::int32_t> vertices;              // local node ids of owned surface vertices
  std::vector<std::array<std::int32_t, 2>> edges;  // owned edges (local node ids)
  std::vector<std::array<std::int32_t, 3>> faces;  // owned triangles (local node ids, outward)
  std::vector<int> vertex_body, edge_body, face_body;
  std::vector<std::int64_t> vertex_gid, edge_gid, face_gid;  // global primitive ids
  // Sizes of the whole surface: global ids lie in [0, num_global_*).
  std::int64_t num_global_vertices = 0;
  std::int64_t num_global_edges = 0;
  std::int64_t num_global_faces = 0;
  // Local element whose boundary face each owned triangle comes from.
  std::vector<std::int32_t> face_element;
};

// Builds this rank's owned surface from mesh.boundary_face_mask and mesh.owned_surface (as
// distribute_mesh fills them). No communication. Throws PartitionError when those fields do
// not match the mesh (wrong sizes, node ids out of range), e.g. for a DistributedMesh that
// was not made by distribute_mesh.
ContactSurface build_contact_surface(const DistributedMesh& mesh);

}  // namespace dipc
