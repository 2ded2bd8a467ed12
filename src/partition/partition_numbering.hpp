// Partition-ordered numbering of a whole HexMesh, given a part per element: node ownership,
// contiguous global node and element ranges per part, and each part's local node list.
// Pure C++ (no MPI): distribute_mesh computes it on rank 0; tests check it serially.
#pragma once
#include <cstdint>
#include <vector>

#include "mesh/hex_mesh.hpp"

namespace dipc {

struct PartitionNumbering {
  int num_parts = 0;
  // Per input node: the lowest part whose elements touch it, or -1 for a node that no
  // element touches (such a node carries no mass or stiffness, so it is left out).
  std::vector<int> node_owner;
  // Per input node: its partition-ordered global id, or -1 for an untouched node. Part p
  // owns [node_offset[p], node_offset[p + 1]), numbered in increasing input id.
  std::vector<std::int64_t> node_global_id;
  std::vector<std::int64_t> node_offset;  // num_parts + 1 entries
  // Input element ids ordered by part, increasing input id within a part; part p's
  // elements are elements_by_part[element_offset[p] .. element_offset[p + 1]) and that
  // position is also their global element id.
  std::vector<std::int64_t> elements_by_part;
  std::vector<std::int64_t> element_offset;  // num_parts + 1 entries

  std::int64_t num_global_nodes() const { return node_offset.back(); }
  std::int64_t num_global_elements() const { return element_offset.back(); }
};

// Numbers `mesh` for the partition `element_part` (one part in [0, num_parts) per element).
// Throws PartitionError when the sizes disagree, a part is out of range or a hex references
// a node outside the mesh (the message names the element).
PartitionNumbering number_partition(const HexMesh& mesh, const std::vector<int>& element_part, int num_parts);

// Input ids of the nodes touched by `part`'s elements, in the local order of DistributedMesh:
// owned nodes by increasing global id, then ghosts by increasing global id.
std::vector<std::int64_t> local_nodes_of_part(const HexMesh& mesh, const PartitionNumbering& numbering, int part);

}  // namespace dipc
