// Boundary faces of a whole HexMesh: the hex faces that belong to exactly one element. They
// are the quads from which the contact surface is built (mesh/surface_mesh.hpp), so their
// corner order fixes the outward orientation of every contact triangle.
//
// Local face numbering of a hex (node order of hex_mesh.hpp, reference coordinates ξ,η,ζ):
// face 2·axis + side lies on the plane {ξ,η,ζ}[axis] = (side ? +1 : -1):
//   face 0: ξ = -1  nodes 0 4 7 3        face 1: ξ = +1  nodes 1 2 6 5
//   face 2: η = -1  nodes 0 1 5 4        face 3: η = +1  nodes 3 7 6 2
//   face 4: ζ = -1  nodes 0 3 2 1        face 5: ζ = +1  nodes 4 5 6 7
// Each face lists its 4 nodes counter-clockwise seen from OUTSIDE the element, so on a
// positively oriented hex (det J > 0) the normal (x1 - x0) × (x3 - x0) points outward
// (right-hand rule).
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "mesh/hex_mesh.hpp"

namespace dipc {

constexpr int kHexFaces = 6;

// The 4 local node indices (0..7) of face `face` (0..5) of a hex, in the order above.
// Throws MeshError for a face outside [0, 6).
std::array<int, 4> hex_face_nodes(int face);

struct BoundaryFace {
  std::int64_t element;  // element id in the HexMesh
  int face;              // local face number, see above
};

// The faces that belong to exactly one element of `mesh` (faces are matched by their sets
// of node ids, so two elements sharing a face must share its 4 nodes), sorted by element,
// then by face. Two bodies meshed with shared nodes are glued: their common faces are not
// boundary. O(number of elements): faces are bucketed by their smallest node id and
// compared within a bucket. Throws MeshError, naming the elements, when a node id is
// outside the mesh or when more than two elements share one face (a non-manifold or
// overlapping mesh, which has no well-defined boundary).
std::vector<BoundaryFace> extract_boundary_faces(const HexMesh& mesh);

}  // namespace dipc
