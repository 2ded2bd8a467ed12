// ContactSet: the contact pairs one rank evaluates — the collision set under the barrier form
// (ContactForm, contact_form.hpp). It holds the rank's owned contact surface and rest vertex
// areas, the ghost surface of the last exchange (and the extra nodes it brings), the
// triangle-mesh obstacles, the candidate pairs of the last broad phase, and the active set
// whose pairs make the Hessian's COO pattern. It evaluates no energy: the form does, on the
// pairs described here.
//
// Distribution. Every surface primitive is owned by one rank (partition/contact_surface.hpp).
// A pair is evaluated by exactly one rank: vertex–triangle and vertex–plane pairs by the
// vertex's owner, edge–edge pairs by the owner of the edge with the smaller global id
// (contact/broad_phase/pair_filter.hpp). Before the potential is evaluated along a Newton
// segment x + αp, ranks exchange only the triangles and edges whose swept, d̂-inflated boxes
// overlap another rank's surface box (partition/ghost_surface_exchange.hpp); their nodes become
// extra local nodes of the potential, so positions and gradient contributions travel with the
// ordinary halo exchange, and Hessian entries to rows owned elsewhere go through COO.
//
// Weights w_k: vertex–triangle and vertex–plane pairs use the vertex's rest area (⅓ of its
// incident rest triangle areas; an obstacle vertex's in its obstacle), edge–edge pairs the mean
// rest area of the end vertices of the edge with the smaller global id (of the body's edge in
// a body–obstacle pair), so κ does not depend on the mesh resolution (area-weighted barrier as
// in IPC Toolkit).
//
// Candidates. In host space the broad phase runs on the CPU (contact/broad_phase/
// find_candidates.hpp) over the surface's current positions; in device space on the device
// (contact/broad_phase/cuda/device_broad_phase.hpp, the same pairs in the same order): the
// surface's primitives are uploaded when an exchange changes them, the search receives device
// arrays, and only the candidate lists come back. Triangle-mesh obstacles take part in both
// (contact_obstacles.hpp: positions prescribed in time, held whole on every rank, each pair
// evaluated by the owner of its body primitive); pairs name their vertices by obstacle_node ids.
//
// Active set and pattern. update_pattern keeps the pairs a predicate calls active, in
// for_each_pair's order; their (kind, global nodes) keys decide when the pattern (and with it
// the matrix) changes. Vertex–plane pairs are always in it (contact_form.hpp says why).
#pragma once
#include <mpi.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <string>
#include <unordered_map>
#include <vector>

#include "contact/broad_phase/cuda/device_broad_phase.hpp"
#include "contact/cuda/contact_kernels.hpp"
#include "contact/distributed/contact_obstacles.hpp"
#include "contact/distributed/contact_parameters.hpp"
#include "contact/obstacle_nodes.hpp"
#include "contact/pair_kind.hpp"
#include "device/memory_space.hpp"
#include "partition/contact_surface.hpp"
#include "partition/distributed_mesh.hpp"
#include "partition/ghost_exchange.hpp"
#include "threads/host_threads.hpp"

namespace dipc {

// Per-step contact timings (this rank's; the caller reduces).
struct ContactStats {
  double broad_phase_seconds = 0;  // candidate search (device space: with the surface uploads)
  double ccd_seconds = 0;
  double barrier_seconds = 0;   // value/gradient/Hessian of the barrier
  double exchange_seconds = 0;  // ghost-surface exchange
  double transfer_seconds = 0;  // device space: pair lists copied to the device
};

class ContactSet {
 public:
  // parameters and stats belong to the caller (the form) and must outlive the set. space:
  // where find_candidates searches (device: device arrays, device broad phase). nodal
  // (optional): a set-up halo exchange of the mesh's nodes (any block size) that the rest
  // vertex areas travel through, instead of a scatter of their own.
  ContactSet(const DistributedMesh& mesh, const ContactParameters& parameters, MemorySpace space, ContactStats* stats,
             const GhostExchange* nodal = nullptr);

  // One candidate pair: its kind, its ext-local nodes ([v, t0, t1, t2], [ea0, ea1, eb0, eb1]
  // or [v]; obstacle vertices as obstacle_node ids, which have no unknowns), weight w_k,
  // mollifier threshold.
  struct PairInfo {
    PairKind kind = PairKind::vertex_triangle;
    std::array<std::int32_t, 4> nodes{-1, -1, -1, -1};
    int count = 0;
    double weight = 0, eps_x = 0;
    const ContactParameters::Plane* plane = nullptr;
    // The plane of a vertex–plane pair (nullptr for the other kinds).
    const double* plane_point() const { return plane ? plane->point.data() : nullptr; }
    const double* plane_normal() const { return plane ? plane->normal.data() : nullptr; }
  };

  // ---- surface and extra nodes ----
  const std::vector<std::int64_t>& extra_nodes() const { return extra_nodes_; }
  // Changes whenever an exchange changes the extra nodes (and so the ext-local ids of the nodes
  // beyond the mesh's): ids kept elsewhere are stale when it moved.
  long numbering_version() const { return numbering_version_; }
  // The ghost-surface exchange for the segment x + αp (host arrays); collective. Returns
  // whether the extra nodes changed.
  bool exchange_ghosts(const double* x, const double* p);
  // Global id of an ext-local node; obstacle nodes keep their (negative) obstacle_node id.
  std::int64_t global_node(std::int32_t ext_local) const;
  // Local id (mesh or extra) of a global node, −1 if it is not known on this rank; obstacle
  // nodes map to themselves.
  std::int32_t local_node(std::int64_t global) const {
    if (is_obstacle_node(global)) return static_cast<std::int32_t>(global);
    const std::int32_t m = mesh_local(global);
    if (m >= 0) return m;
    auto it = extra_local_.find(global);
    return it == extra_local_.end() ? -1 : it->second;
  }
  // Nodes that must stay among the extra nodes whatever the exchanges find (friction pairs).
  void pin_nodes(std::vector<std::int64_t> nodes) { pinned_ = std::move(nodes); }
  // Average rest area of the surface vertices over all ranks (1 without any); collective.
  double average_vertex_area() const;

  // ---- triangle-mesh obstacles (contact_obstacles.hpp) ----
  // Until the first call they stand at t = 0. Evaluations see them at t1; the next segments'
  // broad phase and CCD follow them from t0 to t1 (linearly), so a prescribed motion of the
  // obstacles is checked as the body's steps are.
  void move_obstacles(double t0, double t1);
  // The start of a time step at t: obstacles at t, which friction's sliding is measured from.
  void start_obstacle_step(double t) {
    move_obstacles(t, t);
    obstacles_.mark_step_start();
  }
  // Position of an ext-local node in x, or of an obstacle node (at t1).
  const double* position(const double* x, std::int32_t node) const {
    return is_obstacle_node(node) ? obstacles_.end(obstacle_vertex(node)) : x + 3 * static_cast<std::size_t>(node);
  }
  // The same at the start of the step (x_start the body's positions then).
  const double* step_start_position(const double* x_start, std::int32_t node) const {
    return is_obstacle_node(node) ? obstacles_.step_start(obstacle_vertex(node))
                                  : x_start + 3 * static_cast<std::size_t>(node);
  }
  // Device space: the planes and the obstacle vertices' positions, which the kernels read.
  const device::DeviceContactObstacles& device_obstacles() const { return device_obstacles_; }

  // ---- candidates ----
  // The broad phase along x + αp, α ∈ [0, 1] (host arrays in host space, device arrays in
  // device space).
  void find_candidates(const double* x, const double* p);
  // Calls f(kind, index) for every candidate pair this rank evaluates; false if any call was.
  template <class F>
  bool for_each_pair(F&& f) const;
  // The same on the host threads, kind by kind, each kind's candidates in chunks: f(kind,
  // begin, end, chunk), chunk < host_threads(), for the candidates [begin, end) of that kind.
  // f must be safe to call from several threads at once.
  template <class F>
  void for_each_pair_chunk(F&& f) const;
  // The same pair by pair: f(kind, index, slot) on the host threads, slot the pair's place in
  // for_each_pair's order (for lists in which each pair writes its own place).
  template <class F>
  void for_each_pair_slot(F&& f) const;
  // The candidate lists' sizes, in CandidateKind order.
  std::array<std::size_t, kNumCandidateKinds> candidate_counts() const {
    return {vertex_face_.size(),          edge_edge_.size(),          vertex_plane_.size(),
            vertex_obstacle_face_.size(), edge_obstacle_edge_.size(), obstacle_vertex_face_.size()};
  }
  // Where each kind's candidates start in for_each_pair's order (a pair's slot is its kind's
  // start plus its index), and, last, the number of candidates.
  std::array<std::size_t, kNumCandidateKinds + 1> candidate_starts() const {
    const std::array<std::size_t, kNumCandidateKinds> count = candidate_counts();
    std::array<std::size_t, kNumCandidateKinds + 1> start{};
    for (int k = 0; k < kNumCandidateKinds; ++k) start[k + 1] = start[k] + count[k];
    return start;
  }
  // What keep(kind, index, out) appends to out for every candidate, on the host threads, joined
  // in for_each_pair's order (for any number of threads).
  template <class T, class Keep>
  std::vector<T> collect_pairs(Keep&& keep) const;
  PairInfo describe(CandidateKind kind, std::size_t i) const;
  // Device space: out = the candidate pairs of the last broad phase, described on the device
  // (device::build_candidate_pairs) from their indices: the same list as ContactForm's
  // candidate_pair_list uploaded.
  void describe_on_device(device::DeviceContactPairs* out);
  // Stacked positions of a pair's nodes at x (obstacles at t1) and, for CCD, at the segment's
  // start and end (obstacles from t0 to t1).
  void gather(const double* x, const PairInfo& info, double* X) const;
  void gather_segment(const double* x, const double* p, const PairInfo& info, double* X0, double* X1) const;

  // ---- active set and matrix pattern ----
  struct PatternEntry {
    CandidateKind kind;
    std::int32_t index;  // into the list of that kind
  };
  // Keeps the candidates for which active(kind, index) holds (vertex–plane pairs always) as the
  // pattern's pairs; the version changes when their keys do. active is called from the host
  // threads at once.
  template <class Active>
  void update_pattern(Active&& active);
  const std::vector<PatternEntry>& pattern_pairs() const { return pattern_pairs_; }
  long pattern_version() const { return pattern_version_; }
  // The pattern's pairs' body nodes (global ids, obstacle nodes left out): pair k's in
  // nodes[0 .. returned count). The Hessian's values of a pair are the dense block over them.
  // Safe to call from several host threads at once.
  std::size_t num_pattern_groups() const { return pattern_key_.size(); }
  int pattern_group(std::size_t k, std::int64_t* nodes) const {
    const auto& key = pattern_key_[k];
    const int count = key[0] == static_cast<std::int64_t>(CandidateKind::vertex_plane) ? 1 : 4;
    int slots[4];
    const int n = body_slots(key.data() + 1, count, slots);
    for (int a = 0; a < n; ++a) nodes[a] = key[1 + slots[a]];
    return n;
  }
  // The body-node blocks (global row node, global column node) of every candidate pair but the
  // vertex–plane ones (always in the pattern): room in the matrix for the active set to change
  // within the candidates of the last broad phase (assembly/reserved_blocks.hpp). Appends.
  void reserved_blocks(std::vector<std::array<std::int64_t, 2>>* blocks) const;

  // ---- diagnostics ----
  // Edge–triangle crossings at x between this rank's owned edges and every triangle known
  // here (owned or ghost; call after the potential prepared x), vertices behind a plane, and
  // crossings of owned edges with obstacle triangles and of obstacle edges with owned triangles.
  // Returns how many; *first describes one (bodies and input node ids) for error messages.
  long count_intersections(const double* x, std::string* first) const;
  // The candidate pair closest at x over all ranks, for error messages: its two primitives with
  // their bodies and input node ids and the distance between them ("node 7 of body "upper" and
  // triangle (node 1, node 2, node 3) of body "lower", 0 apart"); "" without any pair.
  // Collective (call after the potential prepared x).
  std::string closest_pair(const double* x) const;

 private:
  // Local id of a global node among the mesh's local nodes, or -1.
  std::int32_t mesh_local(std::int64_t global) const {
    const std::int64_t owned = global - mesh_.node_offset;
    if (owned >= 0 && owned < mesh_.num_owned_nodes) return static_cast<std::int32_t>(owned);
    const auto first = mesh_.local_to_global.begin() + mesh_.num_owned_nodes, last = mesh_.local_to_global.end();
    const auto it = std::lower_bound(first, last, global);
    return it != last && *it == global ? static_cast<std::int32_t>(it - mesh_.local_to_global.begin()) : -1;
  }
  struct Primitive {  // an edge or a triangle known on this rank (owned or ghost)
    std::int64_t gid;
    int body;
    bool owned;
    std::array<std::int32_t, 3> node;  // ext-local node ids (edges use 2)
    double rest_length2 = 0;           // edges: squared rest length (mollifier threshold)
  };
  std::int32_t ext_local(std::int64_t global_node);  // adds an extra node if needed
  void collect_owned();
  // The broad phase's numbering of the surface: compact vertices over every node that a surface
  // vertex or primitive touches (vertex_node: their ext-local nodes), with groups (bodies),
  // owned vertices and edges, and the primitives in compact ids.
  device::BroadPhaseSurface number_surface() const;
  void find_candidates_on_host(const double* x, const double* p);
  void find_candidates_on_device(const double* x, const double* p);
  void upload_surface();  // device space: number_surface() and the obstacles to the device broad phase
  // Device space: what describe() reads, for describe_on_device: the body's part (triangles,
  // edges) after every change of the surface; the vertex areas, the owned edges' weights and
  // the obstacles once (after collect_owned).
  void upload_pair_sources_body();
  void upload_pair_sources_fixed();
  void append_obstacles(device::BroadPhaseSurface* s) const;
  void upload_obstacle_positions();  // device space
  std::string obstacle_vertex_label(std::int32_t v) const;
  std::string obstacle_face_label(std::int32_t f) const;
  std::string obstacle_edge_label(std::int32_t e) const;
  long count_obstacle_intersections(const double* x, std::string* first) const;
  // Names for messages: "\"body name\"" (or the id), "node <input id>".
  std::string body_label(int body) const;
  std::string node_label(std::int32_t node) const;
  std::vector<std::array<std::int64_t, 5>> pattern_keys(const std::vector<PatternEntry>& pairs) const;

  MPI_Comm comm_;
  int rank_ = 0, size_ = 1;
  const DistributedMesh& mesh_;
  const ContactParameters& parameters_;
  MemorySpace space_;
  ContactStats* stats_;
  ContactSurface surface_;
  std::unordered_map<std::int32_t, double> node_area_;  // mesh-local node -> rest vertex area
  std::vector<Primitive> edges_, faces_;                // owned first, then ghosts (rebuilt by exchanges)
  std::size_t owned_edges_ = 0, owned_faces_ = 0;
  std::vector<std::int64_t> extra_nodes_;
  long numbering_version_ = 0;
  std::vector<std::int64_t> pinned_;
  // Local ids of the extra nodes. The mesh's own nodes need no map: owned ones are a
  // contiguous range and ghosts are sorted by global id (distributed_mesh.hpp); a hash map of
  // every local node took 0.1 s per million nodes to build.
  std::unordered_map<std::int64_t, std::int32_t> extra_local_;
  // Candidate pairs this rank evaluates: (vertex node, face index), (edge index, edge index).
  std::vector<std::array<std::int32_t, 2>> vertex_face_, edge_edge_;
  std::vector<std::array<std::int32_t, 2>> vertex_plane_;  // (vertex node, plane), all of them, fixed
  // The triangle-mesh obstacles, and the candidate pairs with them: (vertex node, obstacle face),
  // (edge index, obstacle edge), (obstacle vertex, face index).
  ObstacleSurface obstacles_;
  std::vector<std::array<std::int32_t, 2>> vertex_obstacle_face_, edge_obstacle_edge_, obstacle_vertex_face_;
  // Active pairs at the last update_pattern (their order defines the COO pattern).
  std::vector<PatternEntry> pattern_pairs_;
  std::vector<std::array<std::int64_t, 5>> pattern_key_;  // (kind, global nodes) per active pair
  long pattern_version_ = 0;
  // Device space: the planes and obstacle vertex positions (and the segment times of those
  // positions), the broad phase over the uploaded surface and the ext-local node of each of its
  // compact vertices.
  device::DeviceContactObstacles device_obstacles_;
  double uploaded_t0_ = 0, uploaded_t1_ = 0;  // ObstacleSurface starts at t = 0
  device::DeviceBroadPhase device_broad_phase_;
  device::DevicePairSources device_pair_sources_;
  std::vector<double> owned_edge_weight_;  // device space: per owned edge, as describe() weighs its pairs
  device::Array<std::int32_t> device_candidate_index_{"contact candidate indices"};
  std::vector<std::int32_t> device_surface_nodes_;
  int device_body_vertices_ = 0;  // compact vertices before the obstacles' (append_obstacles)
};

template <class F>
bool ContactSet::for_each_pair(F&& f) const {
  const std::array<std::size_t, kNumCandidateKinds> count = candidate_counts();
  bool ok = true;
  for (int kind = 0; kind < kNumCandidateKinds; ++kind)
    for (std::size_t i = 0; i < count[kind]; ++i) ok = f(static_cast<CandidateKind>(kind), i) && ok;
  return ok;
}

template <class F>
void ContactSet::for_each_pair_chunk(F&& f) const {
  const std::array<std::size_t, kNumCandidateKinds> count = candidate_counts();
  for (int kind = 0; kind < kNumCandidateKinds; ++kind)
    parallel_chunks(count[kind], [&](int chunk, std::size_t begin, std::size_t end) {
      f(static_cast<CandidateKind>(kind), begin, end, chunk);
    });
}

template <class F>
void ContactSet::for_each_pair_slot(F&& f) const {
  const std::array<std::size_t, kNumCandidateKinds + 1> first = candidate_starts();
  for_each_pair_chunk([&](CandidateKind kind, std::size_t begin, std::size_t end, int) {
    for (std::size_t i = begin; i < end; ++i) f(kind, i, first[static_cast<int>(kind)] + i);
  });
}

template <class T, class Keep>
std::vector<T> ContactSet::collect_pairs(Keep&& keep) const {
  const std::array<std::size_t, kNumCandidateKinds> count = candidate_counts();
  std::vector<T> all;
  for (int k = 0; k < kNumCandidateKinds; ++k) {
    const CandidateKind kind = static_cast<CandidateKind>(k);
    const std::vector<T> part =
        parallel_collect<T>(count[k], [&](std::size_t begin, std::size_t end, std::vector<T>& out) {
          for (std::size_t i = begin; i < end; ++i) keep(kind, i, out);
        });
    all.insert(all.end(), part.begin(), part.end());
  }
  return all;
}

template <class Active>
void ContactSet::update_pattern(Active&& active) {
  // Each kind's candidates tested on the host threads (active must be safe to call from
  // several): at 1M hexes there are millions of candidates, asked at every Newton iteration.
  std::vector<PatternEntry> active_now =
      collect_pairs<PatternEntry>([&](CandidateKind kind, std::size_t i, std::vector<PatternEntry>& out) {
        // Vertex–plane pairs are always in the pattern (contact_form.hpp).
        if (kind == CandidateKind::vertex_plane || active(kind, i)) out.push_back({kind, static_cast<std::int32_t>(i)});
      });
  std::vector<std::array<std::int64_t, 5>> key = pattern_keys(active_now);
  pattern_pairs_ = std::move(active_now);
  if (key != pattern_key_) {
    pattern_key_ = std::move(key);
    ++pattern_version_;
  }
}

}  // namespace dipc
