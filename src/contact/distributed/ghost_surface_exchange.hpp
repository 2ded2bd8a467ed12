// The ghost contact surface (docs/design.md §5.3): before the potential is evaluated along a
// Newton segment x + αp, each rank sends every other rank the triangles and edges it owns
// whose boxes — swept along the segment and inflated by the activation distance — reach the
// other rank's own swept surface box, and receives theirs. The contact form (ContactForm in
// src/nonlinear/) turns what arrives into ghost primitives and extra nodes; this file is only
// the collective exchange, on global ids.
#pragma once
#include <mpi.h>

#include <array>
#include <cstdint>
#include <vector>

#include "math/aabb.hpp"

namespace dipc {

// One edge or triangle of the contact surface as it travels between ranks.
struct SurfacePrimitiveRecord {
  std::int64_t is_face = 0;  // 0 edge, 1 triangle
  std::int64_t gid = 0;      // global edge or triangle id (contact_surface.hpp)
  std::int64_t body = 0;
  std::array<std::int64_t, 3> node{-1, -1, -1};  // global node ids; an edge leaves node[2] = −1
  double rest_length2 = 0;                       // edges: squared rest length
};

// Collective over comm. Sends each other rank the records of `owned` whose box (boxes[i], one
// per record) overlaps that rank's reach, and returns the records received from all ranks
// sorted by (is_face, gid), so the result does not depend on the order of arrival. A rank's
// reach is its surface seen through a grid of about 64 cells over its surface box: the union of
// its boxes in each cell (a rank without primitives reaches nothing). Every record whose box
// overlaps one of the receiver's boxes arrives; of the others, only those near a cell's box
// (the cell's union of boxes is larger than the boxes), where one box for a whole rank sent
// whatever lay between its bodies.
std::vector<SurfacePrimitiveRecord> exchange_ghost_surface(MPI_Comm comm,
                                                           const std::vector<SurfacePrimitiveRecord>& owned,
                                                           const std::vector<Aabb>& boxes);

}  // namespace dipc
