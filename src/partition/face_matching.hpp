// Parallel face matching of a sliced mesh (mesh_slice.hpp): every hex face is sent to the home
// rank of its smallest node id, where faces with the same 4 nodes meet. A face met once is on
// the boundary of the whole mesh; a face met twice joins its two elements in the dual graph
// (the graph the partitioners cut). The same rules as extract_boundary_faces
// (mesh/boundary_faces.hpp), without any rank holding the whole mesh: O(elements / ranks)
// work and memory per rank for a balanced node numbering.
#pragma once
#include <cstdint>
#include <vector>

#include "partition/mesh_slice.hpp"

namespace dipc {

struct FaceMatching {
  // Per slice element, bit f set when face f (boundary_faces.hpp numbering) is on the boundary.
  std::vector<std::uint8_t> boundary_mask;
  // Dual graph rows of the slice's elements: the face neighbours (input element ids, sorted)
  // of slice element i are neighbours[offsets[i] .. offsets[i + 1]).
  std::vector<std::int64_t> offsets;
  std::vector<std::int64_t> neighbours;
};

// Collective. Throws PartitionError on every rank when more than two elements share a face
// (the message names them), as a non-manifold or overlapping mesh has no boundary.
FaceMatching match_faces(const MeshSlice& slice);

}  // namespace dipc
