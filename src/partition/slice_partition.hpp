// Element partitioners for a sliced mesh (mesh_slice.hpp), chosen with -dipc_partitioner:
//   metis    - the connectivity (8 ids per element, no coordinates) is gathered on rank 0 and cut
//              by METIS_PartMeshDual (metis_partition.hpp), then the parts are sent back. The
//              same parts as before slices existed; rank 0 holds the dual graph, so it is the
//              choice while one rank can (about 0.3 GB per million elements, measured in
//              bench/setup.py's runs).
//   ptscotch - PT-Scotch through PETSc's MatPartitioning on the distributed dual graph of
//              face_matching.hpp: no rank holds more than its slice.
//   rcb      - recursive coordinate bisection of the element centroids (rcb_partition.hpp):
//              no rank holds more than its slice, no dual graph, a few passes over the slice
//              per level; for meshes too big for METIS on one rank where PETSc has no
//              PT-Scotch (a CUDA build), or where setup time matters more than the edge cut.
// METIS and RCB give the same parts for a given mesh and rank count. PT-Scotch need not: Debian's
// Scotch 7 gave edge cuts 400, 400 and 440 in three 2-rank runs on a 20^3 box, although its
// generator is reset before each call; trajectories then differ at round-off, inside the rank
// invariance tests' tolerances.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "partition/face_matching.hpp"
#include "partition/mesh_slice.hpp"

namespace dipc {

enum class Partitioner { metis, ptscotch, rcb };

// "metis", "ptscotch" or "rcb"; throws PartitionError naming the accepted values otherwise.
Partitioner parse_partitioner(const std::string& name);
const char* partitioner_name(Partitioner p);
// Whether this PETSc has PT-Scotch (PETSC_HAVE_PTSCOTCH; Debian's has, a PETSc configured
// without --download-ptscotch has not). Partitioner::ptscotch throws PartitionError without it.
bool ptscotch_available();

// Collective: the part (= rank) of every slice element.
std::vector<int> partition_slice(const MeshSlice& slice, const FaceMatching& graph, Partitioner partitioner);

// Quality of a partition, the same on every rank: the edge cut (dual-graph edges, i.e. interior
// faces, whose two elements lie in different parts) and the imbalance (largest part over the
// mean part size).
struct PartitionQuality {
  std::int64_t edge_cut = 0;
  std::int64_t dual_edges = 0;
  std::int64_t largest_part = 0, smallest_part = 0;
  double imbalance = 0;
};
// Collective.
PartitionQuality partition_quality(const MeshSlice& slice, const FaceMatching& graph, const std::vector<int>& part);

}  // namespace dipc
