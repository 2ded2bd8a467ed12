// distribute_mesh (declared in distributed_mesh.hpp): rank 0 partitions and numbers the whole
// mesh, packs every rank's part into flat arrays and sends them with MPI_Scatterv; every
// rank rebuilds its DistributedMesh from what it received. Rank 0 holds O(whole mesh), the
// other ranks O(their part). Errors found on rank 0 (bad input, METIS failure) are
// broadcast first, so every rank throws the same PartitionError instead of hanging.
// Nodes that no element touches are left out of the numbering and of the node sets: they
// would carry no mass or stiffness and make the Newton system singular.
// Rank 0 also extracts the boundary surface of the whole mesh (a face is on the boundary only
// if no other element, on any rank, has it) and decides which rank owns each contact
// primitive (partition/surface_owners.hpp); each rank gets its boundary-face masks and its
// owned edges and vertices with their global ids.
// DistributedMesh::comm is `comm` itself (not duplicated); the caller keeps it alive.
#include <algorithm>
#include <climits>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "mesh/surface_mesh.hpp"
#include "partition/distributed_mesh.hpp"
#include "partition/metis_partition.hpp"
#include "partition/partition_error.hpp"
#include "partition/partition_numbering.hpp"
#include "partition/surface_owners.hpp"

namespace dipc {
namespace {

constexpr int kRoot = 0;

// Per-rank counts and offsets sent with MPI_Scatter, kMetaSize values per rank.
enum MetaField {
  kNumOwnedNodes,
  kNumLocalNodes,
  kNumElements,
  kNodeOffset,
  kElementOffset,
  kNumSetMemberships,
  kNumOwnedTriangles,
  kNumOwnedEdges,
  kNumOwnedVertices,
  kMetaSize
};

template <class T>
MPI_Datatype mpi_type();
template <>
MPI_Datatype mpi_type<std::int64_t>() {
  return MPI_INT64_T;
}
template <>
MPI_Datatype mpi_type<std::int32_t>() {
  return MPI_INT32_T;
}
template <>
MPI_Datatype mpi_type<std::uint8_t>() {
  return MPI_UINT8_T;
}
template <>
MPI_Datatype mpi_type<double>() {
  return MPI_DOUBLE;
}

void check_mpi(int status, const char* call) {
  if (status != MPI_SUCCESS) {
    char text[MPI_MAX_ERROR_STRING];
    int length = 0;
    MPI_Error_string(status, text, &length);
    throw PartitionError(std::string("distribute_mesh: ") + call + " failed: " + std::string(text, length));
  }
}

// One flat send array of rank 0 with its per-rank element counts; MPI counts and
// displacements are int, so they are checked before anything is sent.
template <class T>
struct ScatterBlock {
  std::vector<T> data;
  std::vector<int> counts;
  std::vector<int> displs;

  void close_rank(std::size_t begin_of_rank, const char* what, int rank) {
    const std::size_t count = data.size() - begin_of_rank;
    const auto int_max = static_cast<std::size_t>(INT_MAX);
    if (count > int_max || begin_of_rank > int_max) {
      throw PartitionError(std::string("distribute_mesh: the ") + what + " array of rank " + std::to_string(rank) +
                           " does not fit MPI's int counts (" + std::to_string(data.size()) +
                           " entries); use more ranks or a "
                           "smaller mesh");
    }
    counts.push_back(static_cast<int>(count));
    displs.push_back(static_cast<int>(begin_of_rank));
  }
};

// Everything rank 0 sends: per-rank metadata, the node-set names (broadcast) and the
// element and node arrays of every rank, concatenated in rank order.
struct Payload {
  std::int64_t num_global_nodes = 0;
  std::int64_t num_global_elements = 0;
  std::int64_t num_global_triangles = 0;
  std::int64_t num_global_edges = 0;
  std::int64_t num_global_vertices = 0;
  std::vector<std::string> set_names;
  std::vector<std::int64_t> meta;
  ScatterBlock<std::int64_t> element_nodes;  // 8 input node ids per element
  ScatterBlock<std::int32_t> element_body;
  ScatterBlock<std::int64_t> element_input_id;
  ScatterBlock<std::int64_t> node_global_id;
  ScatterBlock<double> node_coordinates;  // 3 per node
  ScatterBlock<std::int64_t> node_input_id;
  ScatterBlock<std::int32_t> set_membership;      // (set index, local node id) pairs
  ScatterBlock<std::uint8_t> boundary_face_mask;  // one per element
  ScatterBlock<std::int64_t> triangle_gid;
  ScatterBlock<std::int32_t> edge_nodes;  // 2 local node ids per owned edge
  ScatterBlock<std::int64_t> edge_gid;
  ScatterBlock<std::int32_t> edge_body;
  ScatterBlock<std::int32_t> vertex_node;  // local node id per owned vertex
  ScatterBlock<std::int64_t> vertex_gid;
  ScatterBlock<std::int32_t> vertex_body;
};

// Primitive indices grouped by owner part (a counting sort): part p's are
// items[begin[p] .. begin[p + 1]), in increasing index, i.e. increasing global id.
struct IndicesByPart {
  std::vector<std::int64_t> begin;
  std::vector<std::int64_t> items;
};

IndicesByPart group_by_part(const std::vector<int>& owner, int num_parts) {
  IndicesByPart groups;
  groups.begin.assign(static_cast<std::size_t>(num_parts) + 1, 0);
  for (int part : owner) ++groups.begin[static_cast<std::size_t>(part) + 1];
  for (int p = 0; p < num_parts; ++p) groups.begin[p + 1] += groups.begin[p];
  groups.items.resize(owner.size());
  std::vector<std::int64_t> next(groups.begin.begin(), groups.begin.end() - 1);
  for (std::size_t i = 0; i < owner.size(); ++i) {
    groups.items[static_cast<std::size_t>(next[owner[i]]++)] = static_cast<std::int64_t>(i);
  }
  return groups;
}

// The whole-mesh surface with its owners, indexed for packing one rank at a time.
struct SurfaceForPacking {
  SurfaceMesh surface;
  std::vector<std::uint8_t> face_mask;   // per input element
  std::vector<std::int64_t> first_quad;  // per input element + 1: its quads' range
  IndicesByPart edges_by_part;
  IndicesByPart vertices_by_part;

  SurfaceForPacking(const HexMesh& mesh, const std::vector<int>& element_part, int num_parts)
      : surface(build_surface_mesh(mesh)) {
    const SurfaceOwners owners = assign_surface_owners(surface, element_part);
    edges_by_part = group_by_part(owners.edge, num_parts);
    vertices_by_part = group_by_part(owners.vertex, num_parts);
    face_mask.assign(mesh.num_elements(), 0);
    first_quad.assign(mesh.num_elements() + 1, 0);
    for (const BoundaryFace& quad : surface.quads) {
      const auto e = static_cast<std::size_t>(quad.element);
      face_mask[e] = static_cast<std::uint8_t>(face_mask[e] | (1u << quad.face));
      ++first_quad[e + 1];
    }
    for (std::size_t e = 0; e < mesh.num_elements(); ++e) first_quad[e + 1] += first_quad[e];
  }
};

// Appends rank `rank`'s boundary-face masks, triangle ids and owned edges and vertices.
// `local_of_input` maps input node ids to the rank's local ids (-1 elsewhere).
void pack_surface(const SurfaceForPacking& s, const PartitionNumbering& numbering,
                  const std::vector<std::int32_t>& local_of_input, int rank, Payload& payload, std::int64_t* meta) {
  const std::size_t mask_begin = payload.boundary_face_mask.data.size();
  const std::size_t triangle_begin = payload.triangle_gid.data.size();
  for (std::int64_t i = numbering.element_offset[rank]; i < numbering.element_offset[rank + 1]; ++i) {
    const auto e = static_cast<std::size_t>(numbering.elements_by_part[i]);
    payload.boundary_face_mask.data.push_back(s.face_mask[e]);
    // Quads of an element are sorted by face, which is the order build_contact_surface
    // walks the mask bits in.
    for (std::int64_t q = s.first_quad[e]; q < s.first_quad[e + 1]; ++q) {
      payload.triangle_gid.data.push_back(2 * q);
      payload.triangle_gid.data.push_back(2 * q + 1);
    }
  }
  payload.boundary_face_mask.close_rank(mask_begin, "boundary face mask", rank);
  payload.triangle_gid.close_rank(triangle_begin, "triangle id", rank);

  // The owner holds a triangle with the primitive, so its nodes are local there; a -1 would
  // mean the ownership rule was broken.
  auto local_id = [&](std::int64_t input, const char* what, std::int64_t gid) {
    const std::int32_t local = local_of_input[static_cast<std::size_t>(input)];
    if (local < 0) {
      throw PartitionError(std::string("distribute_mesh: surface ") + what + " " + std::to_string(gid) +
                           " is owned by rank " + std::to_string(rank) + " but its node " + std::to_string(input) +
                           " is not local there");
    }
    return local;
  };
  const std::size_t edge_nodes_begin = payload.edge_nodes.data.size();
  const std::size_t edge_gid_begin = payload.edge_gid.data.size();
  const std::size_t edge_body_begin = payload.edge_body.data.size();
  const IndicesByPart& edges = s.edges_by_part;
  for (std::int64_t k = edges.begin[rank]; k < edges.begin[rank + 1]; ++k) {
    const std::int64_t gid = edges.items[k];
    const auto& edge = s.surface.edges[static_cast<std::size_t>(gid)];
    payload.edge_nodes.data.push_back(local_id(edge[0], "edge", gid));
    payload.edge_nodes.data.push_back(local_id(edge[1], "edge", gid));
    payload.edge_gid.data.push_back(gid);
    payload.edge_body.data.push_back(s.surface.edge_body[static_cast<std::size_t>(gid)]);
  }
  payload.edge_nodes.close_rank(edge_nodes_begin, "edge node", rank);
  payload.edge_gid.close_rank(edge_gid_begin, "edge id", rank);
  payload.edge_body.close_rank(edge_body_begin, "edge body", rank);

  const std::size_t vertex_node_begin = payload.vertex_node.data.size();
  const std::size_t vertex_gid_begin = payload.vertex_gid.data.size();
  const std::size_t vertex_body_begin = payload.vertex_body.data.size();
  const IndicesByPart& vertices = s.vertices_by_part;
  for (std::int64_t k = vertices.begin[rank]; k < vertices.begin[rank + 1]; ++k) {
    const std::int64_t gid = vertices.items[k];
    const std::int64_t node = s.surface.vertices[static_cast<std::size_t>(gid)];
    payload.vertex_node.data.push_back(local_id(node, "vertex", gid));
    payload.vertex_gid.data.push_back(gid);
    payload.vertex_body.data.push_back(s.surface.vertex_body[static_cast<std::size_t>(gid)]);
  }
  payload.vertex_node.close_rank(vertex_node_begin, "vertex node", rank);
  payload.vertex_gid.close_rank(vertex_gid_begin, "vertex id", rank);
  payload.vertex_body.close_rank(vertex_body_begin, "vertex body", rank);

  meta[kNumOwnedTriangles] = static_cast<std::int64_t>(payload.triangle_gid.data.size() - triangle_begin);
  meta[kNumOwnedEdges] = edges.begin[rank + 1] - edges.begin[rank];
  meta[kNumOwnedVertices] = vertices.begin[rank + 1] - vertices.begin[rank];
}

// Without a contact surface: every surface block of rank `rank` is empty (meta's counts stay 0).
void pack_no_surface(int rank, Payload& payload) {
  payload.boundary_face_mask.close_rank(payload.boundary_face_mask.data.size(), "boundary face mask", rank);
  payload.triangle_gid.close_rank(payload.triangle_gid.data.size(), "triangle id", rank);
  payload.edge_nodes.close_rank(payload.edge_nodes.data.size(), "edge node", rank);
  payload.edge_gid.close_rank(payload.edge_gid.data.size(), "edge id", rank);
  payload.edge_body.close_rank(payload.edge_body.data.size(), "edge body", rank);
  payload.vertex_node.close_rank(payload.vertex_node.data.size(), "vertex node", rank);
  payload.vertex_gid.close_rank(payload.vertex_gid.data.size(), "vertex id", rank);
  payload.vertex_body.close_rank(payload.vertex_body.data.size(), "vertex body", rank);
}

void check_mesh_tags(const HexMesh& mesh) {
  if (mesh.body.size() != mesh.num_elements()) {
    throw PartitionError("distribute_mesh: the mesh has " + std::to_string(mesh.body.size()) + " body ids for " +
                         std::to_string(mesh.num_elements()) + " elements");
  }
  for (const auto& [name, nodes] : mesh.node_sets) {
    for (std::int64_t node : nodes) {
      if (node < 0 || static_cast<std::size_t>(node) >= mesh.num_nodes()) {
        throw PartitionError("distribute_mesh: node set '" + name + "' contains node id " + std::to_string(node) +
                             ", outside [0, " + std::to_string(mesh.num_nodes()) + ")");
      }
    }
  }
}

Payload build_payload(const HexMesh& mesh, int num_ranks, bool with_surface) {
  check_mesh_tags(mesh);
  const std::vector<int> element_part = partition_elements(mesh, num_ranks);
  const PartitionNumbering numbering = number_partition(mesh, element_part, num_ranks);

  std::optional<SurfaceForPacking> whole_surface;
  if (with_surface) whole_surface.emplace(mesh, element_part, num_ranks);

  Payload payload;
  payload.num_global_nodes = numbering.num_global_nodes();
  payload.num_global_elements = numbering.num_global_elements();
  if (whole_surface) {
    payload.num_global_triangles = static_cast<std::int64_t>(whole_surface->surface.triangles.size());
    payload.num_global_edges = static_cast<std::int64_t>(whole_surface->surface.edges.size());
    payload.num_global_vertices = static_cast<std::int64_t>(whole_surface->surface.vertices.size());
  }

  // Node -> sets it belongs to (CSR), so packing a rank's memberships costs O(its nodes).
  const std::size_t nn = mesh.num_nodes();
  std::vector<std::int64_t> sets_of_node_ptr(nn + 1, 0);
  for (const auto& [name, nodes] : mesh.node_sets) {
    payload.set_names.push_back(name);
    for (std::int64_t node : nodes) ++sets_of_node_ptr[node + 1];
  }
  if (payload.set_names.size() > static_cast<std::size_t>(INT32_MAX)) {
    throw PartitionError("distribute_mesh: too many node sets");
  }
  for (std::size_t n = 0; n < nn; ++n) sets_of_node_ptr[n + 1] += sets_of_node_ptr[n];
  std::vector<std::int32_t> sets_of_node(sets_of_node_ptr[nn]);
  {
    std::vector<std::int64_t> next(sets_of_node_ptr.begin(), sets_of_node_ptr.end() - 1);
    std::int32_t set_index = 0;
    for (const auto& entry : mesh.node_sets) {
      for (std::int64_t node : entry.second) sets_of_node[next[node]++] = set_index;
      ++set_index;
    }
  }

  payload.meta.resize(static_cast<std::size_t>(kMetaSize) * num_ranks);
  std::vector<std::int32_t> local_of_input(nn, -1);
  for (int rank = 0; rank < num_ranks; ++rank) {
    const std::vector<std::int64_t> local_nodes = local_nodes_of_part(mesh, numbering, rank);
    if (local_nodes.size() > static_cast<std::size_t>(INT32_MAX)) {
      throw PartitionError("distribute_mesh: rank " + std::to_string(rank) + " would hold " +
                           std::to_string(local_nodes.size()) + " nodes, more than 32-bit local ids allow");
    }
    const std::int64_t element_begin = numbering.element_offset[rank];
    const std::int64_t element_end = numbering.element_offset[rank + 1];

    const std::size_t element_nodes_begin = payload.element_nodes.data.size();
    const std::size_t element_body_begin = payload.element_body.data.size();
    const std::size_t element_input_begin = payload.element_input_id.data.size();
    for (std::int64_t i = element_begin; i < element_end; ++i) {
      const std::int64_t e = numbering.elements_by_part[i];
      const Hex& hex = mesh.hexes[e];
      payload.element_nodes.data.insert(payload.element_nodes.data.end(), hex.begin(), hex.end());
      payload.element_body.data.push_back(mesh.body[e]);
      payload.element_input_id.data.push_back(e);
    }
    payload.element_nodes.close_rank(element_nodes_begin, "element node", rank);
    payload.element_body.close_rank(element_body_begin, "element body", rank);
    payload.element_input_id.close_rank(element_input_begin, "element input id", rank);

    const std::size_t global_begin = payload.node_global_id.data.size();
    const std::size_t coordinates_begin = payload.node_coordinates.data.size();
    const std::size_t input_begin = payload.node_input_id.data.size();
    const std::size_t membership_begin = payload.set_membership.data.size();
    for (std::size_t local = 0; local < local_nodes.size(); ++local) {
      const std::int64_t node = local_nodes[local];
      payload.node_global_id.data.push_back(numbering.node_global_id[node]);
      const Vec3& x = mesh.nodes[node];
      payload.node_coordinates.data.insert(payload.node_coordinates.data.end(), x.begin(), x.end());
      payload.node_input_id.data.push_back(node);
      for (std::int64_t k = sets_of_node_ptr[node]; k < sets_of_node_ptr[node + 1]; ++k) {
        payload.set_membership.data.push_back(sets_of_node[k]);
        payload.set_membership.data.push_back(static_cast<std::int32_t>(local));
      }
    }
    payload.node_global_id.close_rank(global_begin, "node global id", rank);
    payload.node_coordinates.close_rank(coordinates_begin, "node coordinate", rank);
    payload.node_input_id.close_rank(input_begin, "node input id", rank);
    payload.set_membership.close_rank(membership_begin, "node set membership", rank);

    std::int64_t* meta = &payload.meta[static_cast<std::size_t>(kMetaSize) * rank];
    for (std::size_t local = 0; local < local_nodes.size(); ++local) {
      local_of_input[static_cast<std::size_t>(local_nodes[local])] = static_cast<std::int32_t>(local);
    }
    if (whole_surface)
      pack_surface(*whole_surface, numbering, local_of_input, rank, payload, meta);
    else
      pack_no_surface(rank, payload);
    for (std::int64_t node : local_nodes) local_of_input[static_cast<std::size_t>(node)] = -1;

    meta[kNumOwnedNodes] = numbering.node_offset[rank + 1] - numbering.node_offset[rank];
    meta[kNumLocalNodes] = static_cast<std::int64_t>(local_nodes.size());
    meta[kNumElements] = element_end - element_begin;
    meta[kNodeOffset] = numbering.node_offset[rank];
    meta[kElementOffset] = element_begin;
    meta[kNumSetMemberships] = static_cast<std::int64_t>((payload.set_membership.data.size() - membership_begin) / 2);
  }
  return payload;
}

// Rank 0 broadcasts its error message (empty when it succeeded); every rank throws it.
void broadcast_root_error(std::string message, int rank, MPI_Comm comm) {
  std::int64_t length = static_cast<std::int64_t>(message.size());
  check_mpi(MPI_Bcast(&length, 1, MPI_INT64_T, kRoot, comm), "MPI_Bcast");
  if (length == 0) return;
  message.resize(static_cast<std::size_t>(length));
  check_mpi(MPI_Bcast(message.data(), static_cast<int>(length), MPI_CHAR, kRoot, comm), "MPI_Bcast");
  if (rank == kRoot) throw PartitionError(message);
  throw PartitionError(message + " (reported by rank 0)");
}

std::vector<std::string> broadcast_names(const std::vector<std::string>& names, int rank, MPI_Comm comm) {
  // Names are sent as one buffer of NUL-terminated strings.
  std::vector<char> buffer;
  if (rank == kRoot) {
    for (const std::string& name : names) {
      buffer.insert(buffer.end(), name.begin(), name.end());
      buffer.push_back('\0');
    }
    if (buffer.size() > static_cast<std::size_t>(INT_MAX)) {
      throw PartitionError("distribute_mesh: node set names exceed MPI's int count");
    }
  }
  int size = static_cast<int>(buffer.size());
  check_mpi(MPI_Bcast(&size, 1, MPI_INT, kRoot, comm), "MPI_Bcast");
  buffer.resize(size);
  check_mpi(MPI_Bcast(buffer.data(), size, MPI_CHAR, kRoot, comm), "MPI_Bcast");
  std::vector<std::string> result;
  for (auto begin = buffer.begin(); begin != buffer.end();) {
    auto end = std::find(begin, buffer.end(), '\0');
    result.emplace_back(begin, end);
    begin = end == buffer.end() ? end : end + 1;
  }
  return result;
}

template <class T>
std::vector<T> scatter(const ScatterBlock<T>& block, std::int64_t my_count, int rank, MPI_Comm comm) {
  std::vector<T> received(static_cast<std::size_t>(my_count));
  const bool root = rank == kRoot;
  check_mpi(MPI_Scatterv(root ? block.data.data() : nullptr, root ? block.counts.data() : nullptr,
                         root ? block.displs.data() : nullptr, mpi_type<T>(), received.data(),
                         static_cast<int>(my_count), mpi_type<T>(), kRoot, comm),
            "MPI_Scatterv");
  return received;
}

// Local node id of every element corner, from the input ids both arrays carry.
std::vector<std::array<std::int32_t, 8>> localize_elements(const std::vector<std::int64_t>& element_nodes,
                                                           const std::vector<std::int64_t>& node_input_id,
                                                           const std::vector<std::int64_t>& element_input_id,
                                                           int rank) {
  std::vector<std::pair<std::int64_t, std::int32_t>> by_input(node_input_id.size());
  for (std::size_t i = 0; i < node_input_id.size(); ++i) {
    by_input[i] = {node_input_id[i], static_cast<std::int32_t>(i)};
  }
  std::sort(by_input.begin(), by_input.end());
  std::vector<std::array<std::int32_t, 8>> elements(element_nodes.size() / 8);
  for (std::size_t e = 0; e < elements.size(); ++e) {
    for (int k = 0; k < 8; ++k) {
      const std::int64_t input = element_nodes[8 * e + k];
      auto it = std::lower_bound(by_input.begin(), by_input.end(), std::make_pair(input, std::int32_t{INT32_MIN}));
      if (it == by_input.end() || it->first != input) {
        throw PartitionError("distribute_mesh: rank " + std::to_string(rank) + " element " +
                             std::to_string(element_input_id[e]) + " references node " + std::to_string(input) +
                             " that was not sent to this rank");
      }
      elements[e][k] = it->second;
    }
  }
  return elements;
}

}  // namespace

DistributedMesh distribute_mesh(const HexMesh& mesh, MPI_Comm comm, bool with_surface) {
  if (comm == MPI_COMM_NULL) throw PartitionError("distribute_mesh: comm is MPI_COMM_NULL");
  int rank = 0;
  int num_ranks = 1;
  check_mpi(MPI_Comm_rank(comm, &rank), "MPI_Comm_rank");
  check_mpi(MPI_Comm_size(comm, &num_ranks), "MPI_Comm_size");

  Payload payload;
  std::string error;
  if (rank == kRoot) {
    try {
      payload = build_payload(mesh, num_ranks, with_surface);
    } catch (const std::exception& e) {
      error = e.what();
      if (error.empty()) error = "distribute_mesh: failed on rank 0";
    }
  }
  broadcast_root_error(error, rank, comm);

  DistributedMesh part;
  part.comm = comm;
  std::int64_t totals[5] = {payload.num_global_nodes, payload.num_global_elements, payload.num_global_triangles,
                            payload.num_global_edges, payload.num_global_vertices};
  check_mpi(MPI_Bcast(totals, 5, MPI_INT64_T, kRoot, comm), "MPI_Bcast");
  part.num_global_nodes = totals[0];
  part.num_global_elements = totals[1];
  OwnedSurface& surface = part.owned_surface;
  surface.num_global_triangles = totals[2];
  surface.num_global_edges = totals[3];
  surface.num_global_vertices = totals[4];
  const std::vector<std::string> set_names = broadcast_names(payload.set_names, rank, comm);

  std::int64_t meta[kMetaSize];
  check_mpi(MPI_Scatter(rank == kRoot ? payload.meta.data() : nullptr, kMetaSize, MPI_INT64_T, meta, kMetaSize,
                        MPI_INT64_T, kRoot, comm),
            "MPI_Scatter");
  const std::int64_t num_local = meta[kNumLocalNodes];
  const std::int64_t num_elements = meta[kNumElements];
  part.num_owned_nodes = static_cast<int>(meta[kNumOwnedNodes]);
  part.node_offset = meta[kNodeOffset];
  part.element_offset = meta[kElementOffset];

  const std::vector<std::int64_t> element_nodes = scatter(payload.element_nodes, 8 * num_elements, rank, comm);
  const std::vector<std::int32_t> element_body = scatter(payload.element_body, num_elements, rank, comm);
  part.element_input_id = scatter(payload.element_input_id, num_elements, rank, comm);
  part.local_to_global = scatter(payload.node_global_id, num_local, rank, comm);
  const std::vector<double> coordinates = scatter(payload.node_coordinates, 3 * num_local, rank, comm);
  part.node_input_id = scatter(payload.node_input_id, num_local, rank, comm);
  const std::vector<std::int32_t> membership = scatter(payload.set_membership, 2 * meta[kNumSetMemberships], rank,
                                                       comm);
  part.boundary_face_mask = scatter(payload.boundary_face_mask, with_surface ? num_elements : 0, rank, comm);
  surface.triangle_gid = scatter(payload.triangle_gid, meta[kNumOwnedTriangles], rank, comm);
  const std::vector<std::int32_t> edge_nodes = scatter(payload.edge_nodes, 2 * meta[kNumOwnedEdges], rank, comm);
  surface.edge_gid = scatter(payload.edge_gid, meta[kNumOwnedEdges], rank, comm);
  const std::vector<std::int32_t> edge_body = scatter(payload.edge_body, meta[kNumOwnedEdges], rank, comm);
  surface.vertices = scatter(payload.vertex_node, meta[kNumOwnedVertices], rank, comm);
  surface.vertex_gid = scatter(payload.vertex_gid, meta[kNumOwnedVertices], rank, comm);
  const std::vector<std::int32_t> vertex_body = scatter(payload.vertex_body, meta[kNumOwnedVertices], rank, comm);
  payload = Payload();  // rank 0: release the whole-mesh send buffers before rebuilding

  part.element_body.assign(element_body.begin(), element_body.end());
  surface.edges.resize(edge_body.size());
  for (std::size_t k = 0; k < surface.edges.size(); ++k) {
    surface.edges[k] = {edge_nodes[2 * k], edge_nodes[2 * k + 1]};
  }
  surface.edge_body.assign(edge_body.begin(), edge_body.end());
  surface.vertex_body.assign(vertex_body.begin(), vertex_body.end());
  part.coordinates.resize(static_cast<std::size_t>(num_local));
  for (std::size_t i = 0; i < part.coordinates.size(); ++i) {
    part.coordinates[i] = {coordinates[3 * i], coordinates[3 * i + 1], coordinates[3 * i + 2]};
  }
  part.elements = localize_elements(element_nodes, part.node_input_id, part.element_input_id, rank);

  std::vector<std::vector<std::int32_t>*> set_by_index;
  for (const std::string& name : set_names) set_by_index.push_back(&part.node_sets[name]);
  for (std::size_t k = 0; k + 1 < membership.size(); k += 2) {
    set_by_index.at(membership[k])->push_back(membership[k + 1]);
  }
  // Memberships arrive in increasing local id and a node is listed once per set it is in;
  // sort/unique still guards against duplicate ids inside an input set.
  for (auto& entry : part.node_sets) {
    std::vector<std::int32_t>& ids = entry.second;
    std::sort(ids.begin(), ids.end());
    ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  }
  return part;
}

}  // namespace dipc
