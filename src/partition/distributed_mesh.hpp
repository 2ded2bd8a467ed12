// DistributedMesh: one rank's part of a HexMesh after METIS partitioning.
//
// Numbering (partition-ordered): rank r owns a contiguous range of global node ids
// [node_offset, node_offset + num_owned_nodes) and of global element ids
// [element_offset, element_offset + num_elements). A node is owned by the lowest rank whose
// elements touch it. Local node ids list the owned nodes first (local id i <-> global id
// node_offset + i), then the ghost nodes (touched by this rank's elements, owned elsewhere),
// sorted by global id. Unknowns are interlaced: global dof = 3 * global node + component.
#pragma once
#include <mpi.h>

#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "mesh/hex_mesh.hpp"
#include "partition/mesh_slice.hpp"
#include "partition/slice_partition.hpp"

namespace dipc {

// One rank's share of the contact surface of the whole mesh, decided on rank 0 where the
// whole surface is known (rules in partition/surface_owners.hpp) and sent with the elements;
// build_contact_surface (partition/contact_surface.hpp) turns it into triangles, edges and
// vertices. Global ids are positions in the canonical surface of mesh/surface_mesh.hpp:
// dense in [0, num_global_*), unique over ranks and the same for every number of ranks.
struct OwnedSurface {
  std::int64_t num_global_triangles = 0;
  std::int64_t num_global_edges = 0;
  std::int64_t num_global_vertices = 0;
  // Global id of every owned triangle, in build order: local elements in order, their
  // boundary faces by increasing face number, triangle 0 then 1 of each quad.
  std::vector<std::int64_t> triangle_gid;
  // Owned edges, by increasing global id: local node ids, the smaller input node id first.
  std::vector<std::array<std::int32_t, 2>> edges;
  std::vector<std::int64_t> edge_gid;
  std::vector<int> edge_body;
  // Owned vertices, by increasing global id: local node ids.
  std::vector<std::int32_t> vertices;
  std::vector<std::int64_t> vertex_gid;
  std::vector<int> vertex_body;
};

struct DistributedMesh {
  MPI_Comm comm = MPI_COMM_NULL;
  std::int64_t num_global_nodes = 0;
  std::int64_t num_global_elements = 0;

  std::int64_t node_offset = 0;
  int num_owned_nodes = 0;
  std::vector<std::int64_t> local_to_global;  // size num_local_nodes(): owned then ghosts
  std::vector<Vec3> coordinates;              // reference coordinates of local nodes
  std::vector<std::int64_t> node_input_id;    // local node -> id in the input HexMesh

  std::int64_t element_offset = 0;
  std::vector<std::array<std::int32_t, 8>> elements;  // local node ids
  std::vector<int> element_body;
  std::vector<std::int64_t> element_input_id;  // local element -> id in the input HexMesh

  // Per local element, bit f (face numbering of mesh/boundary_faces.hpp) is set when face f
  // of the element lies on the boundary of the WHOLE input mesh (no other element has it).
  // Computed on rank 0 before the split, so faces on the cut between ranks are never set.
  std::vector<std::uint8_t> boundary_face_mask;
  OwnedSurface owned_surface;

  // The input mesh's named node sets restricted to this rank's local nodes (local ids,
  // sorted). Every rank has every name, possibly with an empty list.
  std::map<std::string, std::vector<std::int32_t>> node_sets;

  int num_local_nodes() const { return static_cast<int>(local_to_global.size()); }
  int num_ghost_nodes() const { return num_local_nodes() - num_owned_nodes; }
  int num_elements() const { return static_cast<int>(elements.size()); }
};

// Partitions `mesh` (significant on rank 0 only; other ranks pass an empty mesh) into
// `comm`'s size parts with METIS_PartMeshDual (elements adjacent through faces), and sends
// every rank its part, with its boundary-face masks and owned contact surface (extracted on
// rank 0 from the whole mesh). Deterministic: the same mesh and rank count give the same
// result. Throws PartitionError on every rank when rank 0 fails (also for a face shared by
// more than two elements, which has no boundary to extract).
// with_surface = false (a scene without contact): no surface is extracted, and the parts have
// no boundary-face masks and an empty owned_surface.
DistributedMesh distribute_mesh(const HexMesh& mesh, MPI_Comm comm, bool with_surface = true);

// What distribute_slices measured: the partition's quality and each phase's wall time on this
// rank (seconds).
struct DistributeReport {
  PartitionQuality quality;
  double match_faces = 0, partition = 0, quality_check = 0, elements = 0, nodes = 0, surface = 0;
};

// The same DistributedMesh from a sliced mesh (mesh_slice.hpp), built in parallel: no rank holds
// more than O(its slice + its part), except rank 0 with Partitioner::metis, which holds the
// connectivity while METIS runs. With Partitioner::metis the result equals
// distribute_mesh(gather_whole_mesh(slice), ...) field by field (tests check it). `report`,
// when given, receives the partition's edge cut and imbalance (one more exchange) and the
// phase times. Collective; throws PartitionError on every rank for bad slices, a face shared
// by more than two elements or a partitioner failure.
DistributedMesh distribute_slices(const MeshSlice& slice, Partitioner partitioner, bool with_surface = true,
                                  DistributeReport* report = nullptr);

}  // namespace dipc
