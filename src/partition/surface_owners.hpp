// Ownership of the contact-surface primitives of a whole mesh for a given element partition,
// computed on rank 0 where the whole surface is known. Pure C++ (no MPI); distribute_mesh
// ships each part its share, and tests check the rules serially on chosen partitions.
//
// Rules (each primitive of the whole surface gets exactly one owner part):
//   - a triangle is owned by the part of its element;
//   - an edge or a vertex is owned by the LOWEST part that owns a triangle using it.
// The owner of the nodes (the lowest part touching them) is not used for edges and vertices:
// a part may touch a surface node through an element none of whose boundary faces uses it
// (a re-entrant corner), or hold neither triangle of an edge it has both nodes of. Under the
// rule above the owner always has a triangle with the primitive, hence its nodes as local
// nodes, and can evaluate it without extra data.
#pragma once
#include <vector>

#include "mesh/surface_mesh.hpp"

namespace dipc {

struct SurfaceOwners {
  std::vector<int> triangle;  // owner part per SurfaceMesh triangle
  std::vector<int> edge;      // per SurfaceMesh edge
  std::vector<int> vertex;    // per SurfaceMesh vertex
};

// `element_part` holds the part of every element of the mesh `surface` was built from.
// Throws PartitionError when an element of a quad has no part in element_part.
SurfaceOwners assign_surface_owners(const SurfaceMesh& surface, const std::vector<int>& element_part);

}  // namespace dipc
