// Partition-ordered numbering (see partition_numbering.hpp). Ownership by the lowest
// touching part makes every ghost of part p owned by a part q < p, so a part's ghosts all
// have global ids below its own range.
#include "partition/partition_numbering.hpp"

#include <algorithm>
#include <string>

#include "partition/partition_error.hpp"

namespace dipc {

PartitionNumbering number_partition(const HexMesh& mesh, const std::vector<int>& element_part, int num_parts) {
  const std::size_t ne = mesh.num_elements();
  const std::size_t nn = mesh.num_nodes();
  if (num_parts < 1) {
    throw PartitionError("number_partition: num_parts = " + std::to_string(num_parts));
  }
  if (element_part.size() != ne) {
    throw PartitionError("number_partition: " + std::to_string(element_part.size()) + " part ids for " +
                         std::to_string(ne) + " elements");
  }

  PartitionNumbering numbering;
  numbering.num_parts = num_parts;
  numbering.node_owner.assign(nn, -1);
  numbering.element_offset.assign(num_parts + 1, 0);
  for (std::size_t e = 0; e < ne; ++e) {
    const int part = element_part[e];
    if (part < 0 || part >= num_parts) {
      throw PartitionError("number_partition: element " + std::to_string(e) + " has part " + std::to_string(part) +
                           ", outside [0, " + std::to_string(num_parts) + ")");
    }
    ++numbering.element_offset[part + 1];
    for (int k = 0; k < 8; ++k) {
      const std::int64_t node = mesh.hexes[e][k];
      if (node < 0 || static_cast<std::size_t>(node) >= nn) {
        throw PartitionError("number_partition: element " + std::to_string(e) + " node " + std::to_string(k) +
                             " has id " + std::to_string(node) + ", outside [0, " + std::to_string(nn) + ")");
      }
      int& owner = numbering.node_owner[node];
      if (owner < 0 || part < owner) owner = part;
    }
  }

  for (int p = 0; p < num_parts; ++p) {
    numbering.element_offset[p + 1] += numbering.element_offset[p];
  }
  numbering.elements_by_part.resize(ne);
  std::vector<std::int64_t> next_element(numbering.element_offset.begin(), numbering.element_offset.end() - 1);
  for (std::size_t e = 0; e < ne; ++e) {
    numbering.elements_by_part[next_element[element_part[e]]++] = static_cast<std::int64_t>(e);
  }

  numbering.node_offset.assign(num_parts + 1, 0);
  for (std::size_t n = 0; n < nn; ++n) {
    if (numbering.node_owner[n] >= 0) ++numbering.node_offset[numbering.node_owner[n] + 1];
  }
  for (int p = 0; p < num_parts; ++p) numbering.node_offset[p + 1] += numbering.node_offset[p];
  numbering.node_global_id.assign(nn, -1);
  std::vector<std::int64_t> next_node(numbering.node_offset.begin(), numbering.node_offset.end() - 1);
  for (std::size_t n = 0; n < nn; ++n) {
    const int owner = numbering.node_owner[n];
    if (owner >= 0) numbering.node_global_id[n] = next_node[owner]++;
  }
  return numbering;
}

std::vector<std::int64_t> local_nodes_of_part(const HexMesh& mesh, const PartitionNumbering& numbering, int part) {
  if (part < 0 || part >= numbering.num_parts) {
    throw PartitionError("local_nodes_of_part: part " + std::to_string(part) + " outside [0, " +
                         std::to_string(numbering.num_parts) + ")");
  }
  std::vector<std::int64_t> nodes;
  const std::int64_t begin = numbering.element_offset[part];
  const std::int64_t end = numbering.element_offset[part + 1];
  nodes.reserve(8 * static_cast<std::size_t>(end - begin));
  for (std::int64_t i = begin; i < end; ++i) {
    const Hex& hex = mesh.hexes[numbering.elements_by_part[i]];
    nodes.insert(nodes.end(), hex.begin(), hex.end());
  }
  const auto& global = numbering.node_global_id;
  std::sort(nodes.begin(), nodes.end(), [&global](std::int64_t a, std::int64_t b) { return global[a] < global[b]; });
  nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
  // Ghosts are owned by lower parts, so their global ids precede the owned range: rotate
  // them behind the owned nodes, keeping both groups sorted.
  const auto first_owned = std::find_if(nodes.begin(), nodes.end(),
                                        [&](std::int64_t n) { return numbering.node_owner[n] == part; });
  std::rotate(nodes.begin(), first_owned, nodes.end());
  return nodes;
}

}  // namespace dipc
