// Element partition of a HexMesh with METIS (dual graph: hexes adjacent through a face).
#pragma once
#include <vector>

#include "mesh/hex_mesh.hpp"

namespace dipc {

// Returns the part (0 <= part < nparts) of every element of `mesh`, computed with
// METIS_PartMeshDual with ncommon = 4 (two hexes are neighbours when they share a face), a
// fixed seed and C numbering, so the same mesh and nparts always give the same partition.
// nparts == 1 returns all zeros without calling METIS. Throws PartitionError when
// nparts < 1, nparts > number of elements, a hex references a node id outside the mesh,
// the mesh is too large for METIS's idx_t, or METIS fails (the message names the code).
// METIS may leave a part empty; callers must accept parts without elements.
std::vector<int> partition_elements(const HexMesh& mesh, int nparts);
// The same for a connectivity alone (node ids in [0, num_nodes)); no coordinates are needed.
std::vector<int> partition_elements(const std::vector<Hex>& hexes, std::size_t num_nodes, int nparts);

}  // namespace dipc
