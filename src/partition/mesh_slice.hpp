// MeshSlice: one rank's contiguous share of an input mesh in the INPUT numbering, before
// partitioning, so that no rank has to hold the whole mesh. Rank r holds the nodes
// [block_begin(N, P, r), block_begin(N, P, r + 1)) and the elements
// [block_begin(E, P, r), block_begin(E, P, r + 1)) of an N-node, E-element mesh on P ranks
// (mpi_exchange.hpp), so any rank can tell where a node or element lives. The generated
// boxes, the dipc HDF5 mesh reader and slice_whole_mesh produce slices; distribute_slices
// (distributed_mesh.hpp) partitions and numbers them in parallel.
#pragma once
#include <mpi.h>

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "mesh/hex_mesh.hpp"

namespace dipc {

struct MeshSlice {
  MPI_Comm comm = MPI_COMM_NULL;
  std::int64_t num_global_nodes = 0;
  std::int64_t num_global_elements = 0;
  std::int64_t node_begin = 0;     // input id of nodes[0]
  std::vector<Vec3> nodes;         // this rank's block of node coordinates
  std::int64_t element_begin = 0;  // input id of hexes[0]
  std::vector<Hex> hexes;          // input node ids
  std::vector<int> body;           // per element
  // Every named node set of the mesh (every rank has every name), restricted to this rank's
  // node block: sorted, unique input ids.
  std::map<std::string, std::vector<std::int64_t>> node_sets;
};

// Collective. Cuts `whole` (significant on rank 0 only) into the ranks' slices; rank 0 holds
// the whole mesh meanwhile (the path for Gmsh files, which are read on one rank).
MeshSlice slice_whole_mesh(const HexMesh& whole, MPI_Comm comm);

// Collective. The whole mesh on rank 0 (an empty mesh elsewhere): for whole-mesh checks of
// small meshes and for tests.
HexMesh gather_whole_mesh(const MeshSlice& slice);

// Collective. Throws PartitionError on every rank unless the slice has the block layout above,
// one body id per element, node ids in range and node sets inside the node block.
void check_slice_layout(const MeshSlice& slice);

// Collective. Length of the diagonal of the box around all nodes.
double slice_bounding_box_diagonal(const MeshSlice& slice);

// Collective. A 64-bit digest of the mesh (coordinates, connectivity, bodies) that does not
// depend on the number of ranks: a sum over nodes and elements of a hash of (id, row).
std::uint64_t slice_digest(const MeshSlice& slice);

}  // namespace dipc
