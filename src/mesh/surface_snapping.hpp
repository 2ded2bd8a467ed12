// One-layer surface snapping for voxel meshes: the boundary nodes of a staircase mesh are
// moved onto the closest point of the surface it was cut from, as far as every element stays
// well shaped.
#pragma once
#include <cstdint>

#include "mesh/hex_mesh.hpp"
#include "mesh/triangle_surface.hpp"

namespace dipc {

struct SnapStatistics {
  std::int64_t boundary_nodes = 0;
  std::int64_t moved = 0;       // moved all the way onto the surface
  std::int64_t backed_off = 0;  // moved part of the way (the full move spoiled an element)
  std::int64_t not_moved = 0;   // left in place (no triangle in reach, or every try spoiled)
  double min_det_ratio = 0;     // min over elements of min det J / (h^3 / 8) after snapping
};

// Moves each node of the boundary faces of `mesh` (a voxel mesh of cell size h) towards the
// closest point of `surface` within sqrt(3) h. Every element must keep min det J (over its 8
// corners and 8 Gauss points, hex8::min_jacobian_determinant) >= min_det_ratio * h^3 / 8, the
// value of an undistorted cell being h^3 / 8: while an element is below that, the move of its
// node that went farthest is halved (down to 1/64 of the full move, then none) and the elements
// checked again. Halving one node at a time keeps the element's other nodes on the surface;
// halving them all would distort their other elements in turn. The unsnapped mesh satisfies
// the bound, so the loop ends with every element satisfying it. min_det_ratio must lie in
// (0, 1). Closest points move nodes sideways as well as inward or outward, so the volume is
// not always closer to the enclosed one than the staircase's.
SnapStatistics snap_to_surface(HexMesh& mesh, const TriangleSurface& surface, double h, double min_det_ratio = 0.1);

}  // namespace dipc
