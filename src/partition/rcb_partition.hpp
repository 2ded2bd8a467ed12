// Recursive coordinate bisection (RCB; Berger and Bokhari, IEEE Trans. Computers 36(5), 1987)
// of a sliced mesh's elements by their centroids, in parallel: -dipc_partitioner rcb.
//
// A group of elements that is to become q parts is cut by a plane normal to the longest side of
// the box around its centroids, with round(n * floor(q/2) / q) of its n elements on the low
// side; both sides are cut again until every group is one part. Every group of a level is cut
// at once. A cut's position is the k-th smallest centroid coordinate over all ranks, found by a
// radix selection on the coordinate's ordered bits with digit histograms summed over the ranks
// (MPI_Allreduce), so no rank gathers anything and a rank's work is a few passes over its
// slice per level. Elements whose coordinate equals the cut's (a whole layer of a
// structured grid) are taken by increasing input id, so every cut hits its count exactly.
//
// The parts depend on the mesh and the number of parts only, not on how the mesh is sliced,
// and repeat from run to run. Edge cuts measured (docs/solver.md, "Partitioning"): the least
// of the three partitioners on a cube and on two voxelized round bodies; RCB ignores the
// connectivity, so thin, curved or branched bodies can be cut more and parts left in pieces.
#pragma once
#include <vector>

#include "partition/mesh_slice.hpp"

namespace dipc {

// Collective: the centroid (mean of the 8 corners) of every slice element. A rank asks the
// home ranks of its elements' nodes for their coordinates (one all-to-all each way).
std::vector<Vec3> element_centroids(const MeshSlice& slice);

// Collective: the part (0 <= part < parts) of every slice element. Requires at least `parts`
// elements in the mesh (partition_slice checks).
std::vector<int> rcb_partition(const MeshSlice& slice, int parts);

}  // namespace dipc
