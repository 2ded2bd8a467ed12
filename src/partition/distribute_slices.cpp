// distribute_slices (declared in distributed_mesh.hpp): the partition-ordered DistributedMesh of
// distribute_mesh, built from slices without any rank holding the whole mesh. Every whole-mesh
// question is answered at a "home" rank: a node's home holds its block of the input nodes, an
// element's home its block of the input elements (mesh_slice.hpp), and data moves between
// homes and parts with all-to-all exchanges (mpi_exchange.hpp). The rules, and so the result,
// are those of distribute_mesh for the same element partition:
//   - elements: part p's are its elements by increasing input id, numbered from the sum of
//     the earlier parts' counts;
//   - nodes: owned by the lowest part touching them; part p numbers its owned nodes by
//     increasing input id; untouched nodes are left out;
//   - surface: quads ordered by (element input id, face), triangles 2q and 2q + 1; edges and
//     vertices sorted by input node ids, each owned by the lowest part owning a triangle with
//     it, its body the body of its lowest-numbered triangle (partition/surface_owners.hpp).
#include <algorithm>
#include <array>
#include <bitset>
#include <string>
#include <utility>

#include "mesh/boundary_faces.hpp"
#include "mesh/surface_mesh.hpp"
#include "partition/distributed_mesh.hpp"
#include "partition/face_matching.hpp"
#include "partition/mpi_exchange.hpp"
#include "partition/partition_error.hpp"
#include "partition/slice_partition.hpp"
#include "partition/touched_nodes.hpp"
#include "threads/host_threads.hpp"

namespace dipc {
namespace {

struct ElementRecord {
  std::int64_t input;
  Hex hex;
  std::int64_t first_quad;  // global id of the element's first boundary quad
  std::int32_t body;
  std::uint8_t mask;
  std::uint8_t pad[3];
};

struct NodeReply {
  std::int64_t gid;
  Vec3 x;
};
struct OwnedGid {
  std::int64_t input;
  std::int64_t gid;
};
struct Membership {
  std::int64_t request;  // index into the requester's sorted touched nodes
  std::int32_t set;
  std::int32_t pad;
};

struct EdgeRecord {
  std::int64_t a, b, code;  // code = 3 * triangle gid + side
  std::int32_t body, part;
  bool operator<(const EdgeRecord& o) const {
    if (a != o.a) return a < o.a;
    if (b != o.b) return b < o.b;
    return code < o.code;
  }
};
struct VertexRecord {
  std::int64_t node, triangle;
  std::int32_t body, part;
  bool operator<(const VertexRecord& o) const { return node != o.node ? node < o.node : triangle < o.triangle; }
};
struct OwnedPrimitive {
  std::int64_t gid, a, b;  // b unused for vertices
  std::int32_t body, pad;
};

// The node sets of each node of this rank's block, by increasing set index (the sets' order in
// slice.node_sets): node h's are set[first[h] .. first[h + 1]). One array, not a vector per
// node: a box's "all nodes" set alone made a million small allocations at 1M hexes.
struct HomeSets {
  explicit HomeSets(const MeshSlice& slice) : first(slice.nodes.size() + 1, 0) {
    for (const auto& named : slice.node_sets)
      for (std::int64_t n : named.second) ++first[static_cast<std::size_t>(n - slice.node_begin) + 1];
    for (std::size_t h = 1; h < first.size(); ++h) first[h] += first[h - 1];
    set.resize(first.back());
    std::vector<std::size_t> next(first.begin(), first.end() - 1);
    std::int32_t index = 0;
    for (const auto& named : slice.node_sets) {
      for (std::int64_t n : named.second) set[next[static_cast<std::size_t>(n - slice.node_begin)]++] = index;
      ++index;
    }
  }
  std::vector<std::size_t> first;
  std::vector<std::int32_t> set;
};

// The owned contact surface: triangles from the local elements' boundary masks; edges and
// vertices are decided at the home rank of their (smaller) input node id and sent to their owner.
void build_owned_surface(DistributedMesh& part, const std::vector<std::int64_t>& first_quad,
                         const TouchedNodes& touched, const std::vector<std::int32_t>& local_of_touched,
                         std::int64_t num_quads, std::int64_t num_input_nodes, int rank, int size) {
  OwnedSurface& s = part.owned_surface;
  s.num_global_triangles = 2 * num_quads;
  std::vector<std::vector<EdgeRecord>> edges(size);
  std::vector<std::vector<VertexRecord>> vertices(size);
  for (int e = 0; e < part.num_elements(); ++e) {
    std::int64_t q = first_quad[e];
    for (int f = 0; f < kHexFaces; ++f) {
      if (!(part.boundary_face_mask[e] & (1u << f))) continue;
      const std::array<int, 4> corners = hex_face_nodes(f);
      std::int64_t ids[4];
      for (int i = 0; i < 4; ++i) ids[i] = part.node_input_id[part.elements[e][corners[i]]];
      const int m = quad_split_corner(ids);
      for (int k = 0; k < 2; ++k) {
        const std::int64_t t = 2 * q + k;
        s.triangle_gid.push_back(t);
        const std::array<int, 3> c = quad_triangle_corners(m, k);
        const std::int64_t tri[3] = {ids[c[0]], ids[c[1]], ids[c[2]]};
        for (int i = 0; i < 3; ++i) {
          const std::int64_t u = tri[i], v = tri[(i + 1) % 3];
          const std::int64_t a = std::min(u, v), b = std::max(u, v);
          edges[block_of(a, num_input_nodes, size)].push_back({a, b, 3 * t + i, part.element_body[e], rank});
          vertices[block_of(tri[i], num_input_nodes, size)].push_back({tri[i], t, part.element_body[e], rank});
        }
      }
      ++q;
    }
  }
  std::vector<EdgeRecord> edge_records = exchange_records(std::move(edges), part.comm);
  std::sort(edge_records.begin(), edge_records.end());
  std::vector<VertexRecord> vertex_records = exchange_records(std::move(vertices), part.comm);
  std::sort(vertex_records.begin(), vertex_records.end());

  // Unique edges at this home, numbered after those of the lower homes (whose node ids are smaller).
  std::int64_t unique_edges = 0, unique_vertices = 0;
  for (std::size_t i = 0; i < edge_records.size(); ++i)
    if (i == 0 || edge_records[i].a != edge_records[i - 1].a || edge_records[i].b != edge_records[i - 1].b)
      ++unique_edges;
  for (std::size_t i = 0; i < vertex_records.size(); ++i)
    if (i == 0 || vertex_records[i].node != vertex_records[i - 1].node) ++unique_vertices;
  std::int64_t edge_gid = exclusive_prefix(unique_edges, part.comm, &s.num_global_edges);
  std::int64_t vertex_gid = exclusive_prefix(unique_vertices, part.comm, &s.num_global_vertices);
  std::vector<std::vector<OwnedPrimitive>> owned_edges(size), owned_vertices(size);
  for (std::size_t i = 0; i < edge_records.size();) {
    std::size_t j = i;
    int owner = edge_records[i].part;
    while (j < edge_records.size() && edge_records[j].a == edge_records[i].a && edge_records[j].b == edge_records[i].b)
      owner = std::min(owner, edge_records[j++].part);
    // Records of one edge are sorted by triangle, so the first carries the lowest triangle's body.
    owned_edges[owner].push_back({edge_gid++, edge_records[i].a, edge_records[i].b, edge_records[i].body, 0});
    i = j;
  }
  for (std::size_t i = 0; i < vertex_records.size();) {
    std::size_t j = i;
    int owner = vertex_records[i].part;
    while (j < vertex_records.size() && vertex_records[j].node == vertex_records[i].node)
      owner = std::min(owner, vertex_records[j++].part);
    owned_vertices[owner].push_back({vertex_gid++, vertex_records[i].node, -1, vertex_records[i].body, 0});
    i = j;
  }
  edge_records = std::vector<EdgeRecord>();
  vertex_records = std::vector<VertexRecord>();
  std::vector<OwnedPrimitive> my_edges = exchange_records(std::move(owned_edges), part.comm);
  std::vector<OwnedPrimitive> my_vertices = exchange_records(std::move(owned_vertices), part.comm);
  auto by_gid = [](const OwnedPrimitive& x, const OwnedPrimitive& y) { return x.gid < y.gid; };
  std::sort(my_edges.begin(), my_edges.end(), by_gid);
  std::sort(my_vertices.begin(), my_vertices.end(), by_gid);
  // The owner holds a triangle with the primitive, so its nodes are local; -1 would mean the
  // ownership rule was broken.
  std::string error;
  auto local = [&](std::int64_t input, const char* what, std::int64_t gid) -> std::int32_t {
    const std::int64_t i = touched.position(input);
    const std::int32_t l = i < 0 ? -1 : local_of_touched[static_cast<std::size_t>(i)];
    if (l < 0 && error.empty())
      error = std::string("distribute_slices: surface ") + what + " " + std::to_string(gid) + " is owned by rank " +
              std::to_string(rank) + " but its node " + std::to_string(input) + " is not local there";
    return l;
  };
  for (const OwnedPrimitive& p : my_edges) {
    s.edges.push_back({local(p.a, "edge", p.gid), local(p.b, "edge", p.gid)});
    s.edge_gid.push_back(p.gid);
    s.edge_body.push_back(p.body);
  }
  for (const OwnedPrimitive& p : my_vertices) {
    s.vertices.push_back(local(p.a, "vertex", p.gid));
    s.vertex_gid.push_back(p.gid);
    s.vertex_body.push_back(p.body);
  }
  agree_on_error(part.comm, error);
}

// The element records this rank sends to each part, in chunks on the host threads: each chunk
// counts its elements per part and its quads, then writes its records after the lower chunks'
// (as one pass would). Quads are numbered by (element input id, face): an element's first quad
// id is the count of boundary faces of all lower elements; *num_quads counts them all.
std::vector<std::vector<ElementRecord>> element_records_by_part(const MeshSlice& slice, const FaceMatching& faces,
                                                                const std::vector<int>& element_part, bool with_surface,
                                                                std::int64_t* num_quads) {
  int size = 1;
  MPI_Comm_size(slice.comm, &size);
  std::int64_t slice_quads = 0;
  if (with_surface)
    for (std::uint8_t m : faces.boundary_mask) slice_quads += static_cast<std::int64_t>(std::bitset<8>(m).count());
  std::int64_t next_quad = exclusive_prefix(slice_quads, slice.comm, num_quads);

  const auto parts = static_cast<std::size_t>(size);
  std::vector<std::size_t> count(static_cast<std::size_t>(host_threads()) * parts, 0);
  std::vector<std::int64_t> chunk_quads(static_cast<std::size_t>(host_threads()), 0);
  const auto mask_of = [&](std::size_t e) { return with_surface ? faces.boundary_mask[e] : std::uint8_t{0}; };
  const int chunks = parallel_chunks(slice.hexes.size(), [&](int c, std::size_t begin, std::size_t end) {
    for (std::size_t e = begin; e < end; ++e) {
      ++count[static_cast<std::size_t>(c) * parts + static_cast<std::size_t>(element_part[e])];
      chunk_quads[static_cast<std::size_t>(c)] += static_cast<std::int64_t>(std::bitset<8>(mask_of(e)).count());
    }
  });
  const std::vector<std::size_t> total = chunk_starts(count, chunks, parts);
  std::vector<std::vector<ElementRecord>> outgoing(parts);
  for (std::size_t p = 0; p < parts; ++p) outgoing[p].resize(total[p]);
  for (int c = 0; c < chunks; ++c) next_quad += std::exchange(chunk_quads[static_cast<std::size_t>(c)], next_quad);
  parallel_chunks(slice.hexes.size(), [&](int c, std::size_t begin, std::size_t end) {
    std::int64_t quad = chunk_quads[static_cast<std::size_t>(c)];
    std::size_t* next = &count[static_cast<std::size_t>(c) * parts];
    for (std::size_t e = begin; e < end; ++e) {
      ElementRecord r{};
      r.input = slice.element_begin + static_cast<std::int64_t>(e);
      r.hex = slice.hexes[e];
      r.body = slice.body[e];
      r.mask = mask_of(e);
      r.first_quad = quad;
      quad += static_cast<std::int64_t>(std::bitset<8>(r.mask).count());
      const auto p = static_cast<std::size_t>(element_part[e]);
      outgoing[p][next[p]++] = r;
    }
  });
  return outgoing;
}

// The touched nodes that the ranks asked of this rank's node block (its home), and who asked
// each: by asking rank, each rank's asks in its order (sorted by input id).
struct HomeAsks {
  std::vector<std::int64_t> asked;
  std::vector<int> asker;
};

HomeAsks ask_homes(const std::vector<std::int64_t>& touched, std::int64_t nn_input, MPI_Comm comm, int size) {
  std::vector<std::vector<std::int64_t>> asks(size);
  for (std::int64_t n : touched) asks[block_of(n, nn_input, size)].push_back(n);
  HomeAsks home;
  home.asked = exchange_records(std::move(asks), comm, &home.asker);
  return home;
}

// Each touched node's owner, decided at its home: the lowest part touching it.
std::vector<std::int32_t> node_owners(const MeshSlice& slice, const HomeAsks& home, int size) {
  const std::int64_t home_begin = slice.node_begin;
  std::vector<std::int32_t> home_owner(slice.nodes.size(), INT32_MAX);
  for (std::size_t k = 0; k < home.asked.size(); ++k) {
    std::int32_t& o = home_owner[static_cast<std::size_t>(home.asked[k] - home_begin)];
    o = std::min(o, static_cast<std::int32_t>(home.asker[k]));
  }
  std::vector<std::vector<std::int32_t>> owner_replies(size);
  for (std::size_t k = 0; k < home.asked.size(); ++k)
    owner_replies[home.asker[k]].push_back(home_owner[static_cast<std::size_t>(home.asked[k] - home_begin)]);
  return exchange_records(std::move(owner_replies), slice.comm);
}

// Owned nodes, numbered by increasing input id after the lower parts' nodes (part's count,
// offset and global count of them). Gives the global id of each node of the home block (-1 for
// an untouched node).
std::vector<std::int64_t> number_owned_nodes(DistributedMesh& part, const MeshSlice& slice,
                                             const std::vector<std::int64_t>& touched,
                                             const std::vector<std::int32_t>& owner, int rank, int size) {
  std::int64_t num_owned = 0;
  for (std::int32_t o : owner) num_owned += o == rank;
  part.num_owned_nodes = static_cast<int>(num_owned);
  part.node_offset = exclusive_prefix(num_owned, slice.comm, &part.num_global_nodes);
  std::vector<std::vector<OwnedGid>> gids_home(size);
  std::int64_t next = part.node_offset;
  for (std::size_t i = 0; i < touched.size(); ++i)
    if (owner[i] == rank) gids_home[block_of(touched[i], slice.num_global_nodes, size)].push_back({touched[i], next++});
  std::vector<std::int64_t> home_gid(slice.nodes.size(), -1);
  for (const OwnedGid& g : exchange_records(std::move(gids_home), slice.comm))
    home_gid[static_cast<std::size_t>(g.input - slice.node_begin)] = g.gid;
  return home_gid;
}

// What the homes told this rank of its touched nodes: global id and coordinates in the order
// asked, and the node-set memberships with the home that sent each.
struct NodeAnswers {
  std::vector<NodeReply> replies;
  std::vector<Membership> memberships;
  std::vector<int> membership_home;
};

// Home -> every toucher: global id, coordinates and node-set memberships, in the order asked.
// home_gid is released before the exchanges.
NodeAnswers answer_asks(const MeshSlice& slice, const HomeAsks& home, std::vector<std::int64_t> home_gid, int size) {
  const HomeSets sets_of_home(slice);
  std::vector<std::vector<NodeReply>> node_replies(size);
  std::vector<std::vector<Membership>> memberships(size);
  std::vector<std::int64_t> position(size, 0);
  for (std::size_t k = 0; k < home.asked.size(); ++k) {
    const auto h = static_cast<std::size_t>(home.asked[k] - slice.node_begin);
    const int r = home.asker[k];
    node_replies[r].push_back({home_gid[h], slice.nodes[h]});
    for (std::size_t k = sets_of_home.first[h]; k < sets_of_home.first[h + 1]; ++k)
      memberships[r].push_back({position[r], sets_of_home.set[k], 0});
    ++position[r];
  }
  home_gid = std::vector<std::int64_t>();
  NodeAnswers answers;
  answers.replies = exchange_records(std::move(node_replies), slice.comm);
  answers.memberships = exchange_records(std::move(memberships), slice.comm, &answers.membership_home);
  return answers;
}

// Local order: owned nodes by global id (= by input id), then ghosts by global id. Fills part's
// per-node arrays and gives each touched node's local id.
std::vector<std::int32_t> number_local_nodes(DistributedMesh& part, const std::vector<std::int64_t>& touched,
                                             const std::vector<std::int32_t>& owner,
                                             const std::vector<NodeReply>& replies, int rank) {
  std::vector<std::int32_t> order;
  order.reserve(touched.size());
  for (std::size_t i = 0; i < touched.size(); ++i)
    if (owner[i] == rank) order.push_back(static_cast<std::int32_t>(i));
  for (std::size_t i = 0; i < touched.size(); ++i)
    if (owner[i] != rank) order.push_back(static_cast<std::int32_t>(i));
  std::sort(order.begin() + part.num_owned_nodes, order.end(),
            [&](std::int32_t a, std::int32_t b) { return replies[a].gid < replies[b].gid; });
  std::vector<std::int32_t> local_of_touched(touched.size());
  part.local_to_global.resize(touched.size());
  part.coordinates.resize(touched.size());
  part.node_input_id.resize(touched.size());
  for (std::size_t l = 0; l < order.size(); ++l) {
    const std::int32_t i = order[l];
    local_of_touched[i] = static_cast<std::int32_t>(l);
    part.local_to_global[l] = replies[i].gid;
    part.coordinates[l] = replies[i].x;
    part.node_input_id[l] = touched[i];
  }
  return local_of_touched;
}

// part's node sets (every set of the slice, empty ones too) from the memberships the homes sent.
void fill_node_sets(DistributedMesh& part, const MeshSlice& slice, const NodeAnswers& answers,
                    const std::vector<std::int64_t>& touched, const std::vector<std::int32_t>& local_of_touched,
                    int size) {
  // A membership's `request` counts the asks sent to its home; touched nodes are sorted and
  // homes hold increasing blocks, so the asks to home h start at the first touched id in h.
  std::vector<std::int64_t> first_ask(size + 1, 0);
  for (std::int64_t n : touched) ++first_ask[block_of(n, slice.num_global_nodes, size) + 1];
  for (int r = 0; r < size; ++r) first_ask[r + 1] += first_ask[r];
  std::vector<std::vector<std::int32_t>*> by_index;
  for (const auto& named : slice.node_sets) by_index.push_back(&part.node_sets[named.first]);
  std::vector<std::size_t> members(by_index.size(), 0);
  for (const Membership& m : answers.memberships) ++members[m.set];
  for (std::size_t set = 0; set < members.size(); ++set) by_index[set]->reserve(members[set]);
  for (std::size_t k = 0; k < answers.memberships.size(); ++k) {
    const Membership& m = answers.memberships[k];
    by_index[m.set]->push_back(local_of_touched[first_ask[answers.membership_home[k]] + m.request]);
  }
  // Members arrive by increasing input id, so a set of owned nodes only (every set on one
  // rank) is sorted already, and std::sort does not notice (20 ms for a 1M-node set).
  for (auto* ids : by_index)
    if (!std::is_sorted(ids->begin(), ids->end())) std::sort(ids->begin(), ids->end());
}

// part's elements in local node ids, their bodies and input ids, and with the surface their
// boundary faces; gives each element's first quad id (with the surface only).
std::vector<std::int64_t> fill_elements(DistributedMesh& part, const std::vector<ElementRecord>& mine,
                                        const TouchedNodes& touched_nodes,
                                        const std::vector<std::int32_t>& local_of_touched, bool with_surface) {
  std::vector<std::int64_t> first_quad(with_surface ? mine.size() : 0);
  part.boundary_face_mask.resize(with_surface ? mine.size() : 0);
  part.elements.resize(mine.size());
  part.element_body.resize(mine.size());
  part.element_input_id.resize(mine.size());
  parallel_for(mine.size(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t e = begin; e < end; ++e) {
      for (int k = 0; k < 8; ++k)
        part.elements[e][k] = local_of_touched[static_cast<std::size_t>(touched_nodes.position(mine[e].hex[k]))];
      part.element_body[e] = mine[e].body;
      part.element_input_id[e] = mine[e].input;
      if (with_surface) {
        part.boundary_face_mask[e] = mine[e].mask;
        first_quad[e] = mine[e].first_quad;
      }
    }
  });
  return first_quad;
}

}  // namespace

DistributedMesh distribute_slices(const MeshSlice& slice, Partitioner partitioner, bool with_surface,
                                  DistributeReport* report) {
  DistributeReport times;
  double t = MPI_Wtime();
  auto lap = [&t](double& into) {
    const double now = MPI_Wtime();
    into += now - t;
    t = now;
  };
  check_slice_layout(slice);
  MPI_Comm comm = slice.comm;
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  const std::int64_t nn_input = slice.num_global_nodes;

  FaceMatching faces = match_faces(slice);
  lap(times.match_faces);
  const std::vector<int> element_part = partition_slice(slice, faces, partitioner);
  lap(times.partition);
  if (report) times.quality = partition_quality(slice, faces, element_part);
  lap(times.quality_check);

  // Elements to their parts.
  std::int64_t num_quads = 0;
  std::vector<std::vector<ElementRecord>> outgoing = element_records_by_part(slice, faces, element_part, with_surface,
                                                                             &num_quads);
  faces = FaceMatching();
  std::vector<ElementRecord> mine = exchange_records(std::move(outgoing), comm);
  // `mine` is sorted by input id without a sort: records arrive by sending rank, ranks hold
  // increasing blocks of input ids and each sends its own in increasing order.

  DistributedMesh part;
  part.comm = comm;
  part.element_offset = exclusive_prefix(static_cast<std::int64_t>(mine.size()), comm, &part.num_global_elements);

  lap(times.elements);
  // Touched nodes, sorted by input id; their homes decide the owner (the lowest touching part).
  const TouchedNodes touched_nodes(mine.size(), [&mine](std::size_t e) -> const Hex& { return mine[e].hex; });
  const std::vector<std::int64_t>& touched = touched_nodes.ids();
  std::string error;
  if (touched.size() > static_cast<std::size_t>(INT32_MAX))
    error = "distribute_slices: rank " + std::to_string(rank) + " would hold " + std::to_string(touched.size()) +
            " nodes, more than 32-bit local ids allow";
  agree_on_error(comm, error);
  const HomeAsks home = ask_homes(touched, nn_input, comm, size);
  const std::vector<std::int32_t> owner = node_owners(slice, home, size);
  std::vector<std::int64_t> home_gid = number_owned_nodes(part, slice, touched, owner, rank, size);
  const NodeAnswers answers = answer_asks(slice, home, std::move(home_gid), size);
  const std::vector<std::int32_t> local_of_touched = number_local_nodes(part, touched, owner, answers.replies, rank);
  fill_node_sets(part, slice, answers, touched, local_of_touched, size);
  const std::vector<std::int64_t> first_quad = fill_elements(part, mine, touched_nodes, local_of_touched, with_surface);
  mine = std::vector<ElementRecord>();
  lap(times.nodes);
  if (with_surface)
    build_owned_surface(part, first_quad, touched_nodes, local_of_touched, num_quads, nn_input, rank, size);
  lap(times.surface);
  if (report) *report = times;
  return part;
}

}  // namespace dipc
