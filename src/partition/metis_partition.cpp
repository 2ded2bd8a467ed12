// METIS_PartMeshDual wrapper: converts HexMesh connectivity to METIS's CSR mesh format
// (eptr/eind, METIS 5.1 manual, section 5.6) and checks every size against idx_t.
#include "partition/metis_partition.hpp"

#include <metis.h>

#include <limits>
#include <string>

#include "partition/partition_error.hpp"

namespace dipc {
namespace {

constexpr int kNodesPerHex = 8;
// Hexes are neighbours in the dual graph when they share a face, i.e. 4 nodes (METIS 5.1
// manual, METIS_PartMeshDual: "ncommon ... 4 for hexahedra" to get face adjacency).
constexpr idx_t kCommonNodesForFace = 4;

const char* metis_status_name(int status) {
  switch (status) {
    case METIS_OK: return "METIS_OK";
    case METIS_ERROR_INPUT: return "METIS_ERROR_INPUT";
    case METIS_ERROR_MEMORY: return "METIS_ERROR_MEMORY";
    case METIS_ERROR: return "METIS_ERROR";
    default: return "unknown METIS status";
  }
}

}  // namespace

std::vector<int> partition_elements(const HexMesh& mesh, int nparts) {
  return partition_elements(mesh.hexes, mesh.num_nodes(), nparts);
}

std::vector<int> partition_elements(const std::vector<Hex>& hexes, std::size_t num_nodes, int nparts) {
  const std::size_t ne = hexes.size();
  const std::size_t nn = num_nodes;
  if (nparts < 1) {
    throw PartitionError("partition_elements: nparts = " + std::to_string(nparts) + " (must be at least 1)");
  }
  if (ne == 0) throw PartitionError("partition_elements: the mesh has no elements");
  if (static_cast<std::size_t>(nparts) > ne) {
    throw PartitionError("partition_elements: cannot split " + std::to_string(ne) + " elements into " +
                         std::to_string(nparts) + " parts (more parts than elements)");
  }
  const auto idx_max = static_cast<std::size_t>(std::numeric_limits<idx_t>::max());
  if (ne > idx_max / kNodesPerHex || nn > idx_max) {
    throw PartitionError("partition_elements: " + std::to_string(ne) + " elements / " + std::to_string(nn) +
                         " nodes exceed METIS's " + std::to_string(IDXTYPEWIDTH) + "-bit idx_t");
  }

  std::vector<idx_t> eptr(ne + 1);
  std::vector<idx_t> eind(kNodesPerHex * ne);
  for (std::size_t e = 0; e < ne; ++e) {
    eptr[e] = static_cast<idx_t>(kNodesPerHex * e);
    for (int k = 0; k < kNodesPerHex; ++k) {
      const std::int64_t node = hexes[e][k];
      if (node < 0 || static_cast<std::size_t>(node) >= nn) {
        throw PartitionError("partition_elements: element " + std::to_string(e) + " node " + std::to_string(k) +
                             " has id " + std::to_string(node) + ", outside [0, " + std::to_string(nn) + ")");
      }
      eind[kNodesPerHex * e + k] = static_cast<idx_t>(node);
    }
  }
  eptr[ne] = static_cast<idx_t>(kNodesPerHex * ne);

  // One part is trivial; METIS 5.1 has no shortcut for it and would still build the dual
  // graph and run its multilevel scheme.
  if (nparts == 1) return std::vector<int>(ne, 0);

  idx_t options[METIS_NOPTIONS];
  METIS_SetDefaultOptions(options);
  options[METIS_OPTION_SEED] = 0;       // fixed seed: deterministic partitions
  options[METIS_OPTION_NUMBERING] = 0;  // C-style 0-based eptr/eind

  idx_t metis_ne = static_cast<idx_t>(ne);
  idx_t metis_nn = static_cast<idx_t>(nn);
  idx_t ncommon = kCommonNodesForFace;
  idx_t metis_nparts = nparts;
  idx_t edge_cut = 0;
  std::vector<idx_t> element_part(ne);
  std::vector<idx_t> node_part(nn > 0 ? nn : 1);
  const int status = METIS_PartMeshDual(&metis_ne, &metis_nn, eptr.data(), eind.data(), nullptr, nullptr, &ncommon,
                                        &metis_nparts, nullptr, options, &edge_cut, element_part.data(),
                                        node_part.data());
  if (status != METIS_OK) {
    throw PartitionError("partition_elements: METIS_PartMeshDual failed with " +
                         std::string(metis_status_name(status)) + " (" + std::to_string(status) + ") for " +
                         std::to_string(ne) + " elements into " + std::to_string(nparts) + " parts");
  }

  std::vector<int> part(ne);
  for (std::size_t e = 0; e < ne; ++e) {
    if (element_part[e] < 0 || element_part[e] >= metis_nparts) {
      throw PartitionError("partition_elements: METIS returned part " + std::to_string(element_part[e]) +
                           " for element " + std::to_string(e) + ", outside [0, " + std::to_string(nparts) + ")");
    }
    part[e] = static_cast<int>(element_part[e]);
  }
  return part;
}

}  // namespace dipc
