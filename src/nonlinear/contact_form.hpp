// ContactForm: IPC's barrier potential B(x) = κ Σ_k w_k b(d_k(x)) over the contact pairs of the
// whole (distributed) surface — point–triangle, edge–edge (mollified near parallel edges),
// point–plane for half-space obstacles, and the point–triangle and edge–edge pairs between the
// bodies and triangle-mesh obstacles (contact_obstacles.hpp: positions prescribed in time, held
// whole on every rank, each pair evaluated by the owner of its body primitive) — with its CCD
// step bound (Li et al. 2020, §4).
//
// Distribution. Every surface primitive is owned by one rank (partition/contact_surface.hpp).
// A pair is evaluated by exactly one rank: vertex–triangle and vertex–plane pairs by the
// vertex's owner, edge–edge pairs by the owner of the edge with the smaller global id. Before
// the potential is evaluated along a Newton segment x + αp, ranks exchange only the triangles
// and edges whose swept, d̂-inflated boxes overlap another rank's surface box (the "ghost
// surface", partition/ghost_surface_exchange.hpp); their nodes become extra local nodes of the
// potential, so positions and gradient contributions travel with the ordinary halo exchange,
// and Hessian entries to rows owned elsewhere go through COO.
//
// Weights w_k: vertex–triangle and vertex–plane pairs use the vertex's rest area (⅓ of its
// incident rest triangle areas; an obstacle vertex's in its obstacle), edge–edge pairs the mean
// rest area of the end vertices of the edge with the smaller global id (of the body's edge in
// a body–obstacle pair),
// so κ does not depend on the mesh resolution (area-weighted barrier as in IPC Toolkit).
//
// Matrix pattern. The Hessian's COO pattern holds the pairs active at the last update_pattern,
// and a change of that set means a new matrix (rebuilt COO preallocation of the whole
// potential: 1.6 s at 64,000 hexes on 2 cores, far more on one GPU at 1M). Vertex–plane pairs
// are exempt: every owned surface vertex is paired with every plane for the whole run, and all
// those pairs are in the pattern from the first matrix on, writing zeros while inactive. Their
// 3×3 blocks lie on their vertex's diagonal block, which the elastic pattern already holds, so
// the matrix's nonzeros are the same and only vertex–triangle and edge–edge contacts change the
// pattern. An inactive pair's barrier is exactly zero, so values are unchanged; the cost is
// evaluating surface vertices × planes pairs, a small part of the broad phase's work.
//
// Memory space. On the host (the default) every evaluation loops over the pairs on the CPU. On
// the device the broad phase runs there too: the surface's primitives are uploaded when an
// exchange changes them, and prepare_segment, which then receives device arrays, searches the
// candidates with contact/broad_phase/cuda/device_broad_phase.hpp (the same pairs in the same
// order as the host's search), brings the candidate lists back to the host once and uploads the
// pair list built from them. value, gradient, hessian and max_step run the CUDA kernels of
// contact/cuda/contact_kernels.hpp on device arrays; both spaces call the point functions of
// contact/contact_pair_terms.hpp. update_extra_nodes and update_pattern receive host arrays in both
// spaces (update_pattern uploads the pattern's pairs when they change), and so do the queries
// min_distance, active_pairs and count_intersections, which stay on the CPU. Triangle-mesh
// obstacles are evaluated in both spaces: the device holds their vertices' positions (uploaded
// when move_obstacles changes the segment's times) and all their primitives join the device
// broad phase (append_obstacles); pairs name their vertices by obstacle_node ids in both.
// Both spaces search every pair's time of impact on [0, 1] and take the minimum, so the step
// bound is the same bit for bit on the host and the device, and does not depend on the order
// of the pairs (which differs between rank counts). Searching up to the running minimum
// instead would end some searches sooner, but the bound would then depend on that order.
#pragma once
#include <mpi.h>

#include <array>
#include <string>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "contact/broad_phase/cuda/device_broad_phase.hpp"
#include "contact/cuda/contact_kernels.hpp"
#include "contact/pair_kind.hpp"
#include "nonlinear/contact_obstacles.hpp"
#include "nonlinear/contact_parameters.hpp"
#include "nonlinear/form.hpp"
#include "partition/contact_surface.hpp"
#include "partition/distributed_mesh.hpp"

namespace dipc {

struct ContactPairTerms;

// The candidate lists ContactForm keeps, in the order for_each_pair visits them and the per-step
// contact counts report them (pair_kind_name): vertex–triangle, edge–edge, vertex–plane (bodies
// and planes), then body vertex–obstacle triangle, body edge–obstacle edge, obstacle vertex–body
// triangle. Each list's pairs are of one PairKind (candidate_pair_kind).
enum class CandidateKind : int {
  vertex_face = 0,
  edge_edge = 1,
  vertex_plane = 2,
  vertex_obstacle_face = 3,
  edge_obstacle_edge = 4,
  obstacle_vertex_face = 5
};
constexpr int kNumCandidateKinds = 6;

// Per-step contact timings (this rank's; the caller reduces).
struct ContactStats {
  double broad_phase_seconds = 0;  // candidate search (device space: with the surface uploads)
  double ccd_seconds = 0;
  double barrier_seconds = 0;     // value/gradient/Hessian of the barrier
  double exchange_seconds = 0;    // ghost-surface exchange
  double transfer_seconds = 0;    // device space: pair lists copied to the device
};

class ContactForm : public Form {
 public:
  // space: where value, gradient, hessian and max_step run (and where their arrays live).
  // MemorySpace::device throws device::DeviceError when no CUDA device is available.
  ContactForm(const DistributedMesh& mesh, ContactParameters parameters, MemorySpace space = MemorySpace::host);
  std::string name() const override { return "contact barrier"; }
  MemorySpace memory_space() const override { return space_; }
  bool value(const double* x, double* energy) override;
  bool gradient(const double* x, double* g) override;
  void coo_pattern(std::vector<PetscInt>* rows, std::vector<PetscInt>* cols) override;
  bool hessian(const double* x, double* values) override;
  double max_step(const double* x, const double* p) override;
  const std::vector<std::int64_t>* extra_nodes() const override { return &extra_nodes_; }
  bool update_extra_nodes(const double* x, const double* p) override;
  void prepare_segment(const double* x, const double* p) override;
  void update_pattern(const double* x) override;
  long pattern_version() const override { return pattern_version_; }
  bool pattern_may_change() const override { return true; }
  bool limits_step() const override { return true; }

  double kappa() const { return parameters_.kappa; }
  void set_kappa(double kappa) { parameters_.kappa = kappa; }
  // Bounds of the adaptive stiffness (IPC supplement): κ_min from the average nodal mass,
  // κ_max = 100 κ_min. Collective.
  void set_kappa_bounds(double average_mass, double bbox_diagonal);
  double kappa_min() const { return kappa_min_; }
  double kappa_max() const { return kappa_max_; }
  // IPC's "tiny distance" threshold ε_d² = (1e-9 L)² of the stiffness update.
  double min_distance_threshold2() const { return min_distance_eps2_; }
  bool kappa_adaptive() const { return parameters_.kappa_adaptive; }
  // Smallest distance (unsquared) over this rank's candidate pairs at x (and ∞ without pairs).
  double min_distance(const double* x) const;
  const ContactStats& stats() const { return stats_; }
  void reset_stats() { stats_ = ContactStats{}; }
  double dhat() const { return parameters_.dhat; }

  // Triangle-mesh obstacles (contact_obstacles.hpp). Until the first call they stand at t = 0.
  // Evaluations see them at t1; the next segments' broad phase and CCD follow them from t0 to
  // t1 (linearly), so a prescribed motion of the obstacles is checked as the body's steps are.
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

  // One candidate pair: its kind, its ext-local
  // nodes ([v, t0, t1, t2], [ea0, ea1, eb0, eb1] or [v]; obstacle vertices as obstacle_node
  // ids, which have no unknowns), weight w_k, mollifier threshold.
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
  // Pairs active at x (d < d̂), for friction; `first_global` tells pairs apart across exchanges.
  struct ActivePair {
    PairInfo info;
    std::int64_t first_global;
  };
  std::vector<ActivePair> active_pairs(const double* x) const;
  // This rank's active pairs at x per CandidateKind, indexed by its value (output: the per-step
  // contact counts).
  static constexpr int num_pair_kinds = kNumCandidateKinds;
  static const char* pair_kind_name(int kind);  // kind: a CandidateKind's value
  std::array<long, num_pair_kinds> active_pair_counts(const double* x) const;
  // Squared distance of a pair whose stacked node positions are X (3 per node of info.nodes).
  static double squared_distance(const PairInfo& info, const double* X);
  // Global id of an ext-local node; obstacle nodes keep their (negative) obstacle_node id.
  std::int64_t global_node(std::int32_t ext_local) const;
  // Local id (mesh or extra) of a global node, −1 if it is not known on this rank; obstacle
  // nodes map to themselves.
  std::int32_t local_node(std::int64_t global) const {
    if (is_obstacle_node(global)) return static_cast<std::int32_t>(global);
    auto it = global_to_local_.find(global);
    return it == global_to_local_.end() ? -1 : it->second;
  }
  // Nodes that must stay among the extra nodes whatever the exchanges find (friction pairs).
  void pin_nodes(std::vector<std::int64_t> nodes) { pinned_ = std::move(nodes); }
  const ContactParameters& parameters() const { return parameters_; }

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
  void find_candidates(const double* x, const double* p);           // host arrays
  void find_candidates_on_device(const double* x, const double* p);  // device arrays
  void upload_surface();  // device space: number_surface() and the obstacles to the device broad phase
  void append_obstacles(device::BroadPhaseSurface* s) const;
  void upload_obstacle_positions();  // device space
  // Calls f(kind, index) for every candidate pair this rank evaluates; false if any call was.
  template <class F>
  bool for_each_pair(F&& f) const;
  // Stacked positions of a pair's nodes at x (obstacles at t1) and, for CCD, at the segment's
  // start and end (obstacles from t0 to t1).
  void gather(const double* x, const PairInfo& info, double* X) const;
  void gather_segment(const double* x, const double* p, const PairInfo& info, double* X0, double* X1) const;
  std::string obstacle_vertex_label(std::int32_t v) const;
  std::string obstacle_face_label(std::int32_t f) const;
  std::string obstacle_edge_label(std::int32_t e) const;
  long count_obstacle_intersections(const double* x, std::string* first) const;
  PairInfo describe(CandidateKind kind, std::size_t i) const;
  // Names for messages: "\"body name\"" (or the id), "node <input id>".
  std::string body_label(int body) const;
  std::string node_label(std::int32_t node) const;
  bool terms(const PairInfo& info, const double* x, bool want_g, bool want_H, bool* active,
             ContactPairTerms* t) const;
  void append(device::ContactPairList* list, const PairInfo& info) const;
  device::BarrierConstants barrier_constants() const;

  MPI_Comm comm_;
  int rank_ = 0, size_ = 1;
  const DistributedMesh& mesh_;
  ContactParameters parameters_;
  MemorySpace space_;
  ContactSurface surface_;
  std::vector<double> vertex_area_;   // per owned surface vertex (rest)
  std::unordered_map<std::int32_t, double> node_area_;  // mesh-local node -> rest vertex area
  std::vector<Primitive> edges_, faces_;  // owned first, then ghosts (rebuilt by exchanges)
  std::size_t owned_edges_ = 0, owned_faces_ = 0;
  std::vector<std::int64_t> extra_nodes_;
  std::vector<std::int64_t> pinned_;
  std::unordered_map<std::int64_t, std::int32_t> global_to_local_;
  // Candidate pairs this rank evaluates: (vertex node, face index), (edge index, edge index).
  std::vector<std::array<std::int32_t, 2>> vertex_face_, edge_edge_;
  std::vector<std::array<std::int32_t, 2>> vertex_plane_;  // (vertex node, plane), all of them, fixed
  // The triangle-mesh obstacles, and the candidate pairs with them: (vertex node, obstacle face),
  // (edge index, obstacle edge), (obstacle vertex, face index).
  ObstacleSurface obstacles_;
  std::vector<std::array<std::int32_t, 2>> vertex_obstacle_face_, edge_obstacle_edge_, obstacle_vertex_face_;
  // Active pairs at the last update_pattern (their order defines the COO pattern).
  struct PatternEntry {
    CandidateKind kind;
    std::int32_t index;  // into the list of that kind
  };
  std::vector<PatternEntry> pattern_pairs_;
  std::vector<std::array<std::int64_t, 5>> pattern_keys(const std::vector<PatternEntry>& pairs) const;
  std::vector<std::array<std::int64_t, 5>> pattern_key_;  // (kind, global nodes) per active pair
  long pattern_version_ = 0;
  // Device space: the candidates, the pattern's pairs (and the host copy they were uploaded
  // from, to upload only changes), the planes and obstacle vertex positions (and the segment
  // times of those positions), and the reducer that brings scalars back.
  device::DeviceContactPairs device_candidates_, device_pattern_;
  device::ContactPairList uploaded_pattern_;
  device::DeviceContactObstacles device_obstacles_;
  double uploaded_t0_ = 0, uploaded_t1_ = 0;  // ObstacleSurface starts at t = 0
  device::Reducer reducer_;
  // Device space: the broad phase over the uploaded surface and the ext-local node of each of
  // its compact vertices.
  device::DeviceBroadPhase device_broad_phase_;
  std::vector<std::int32_t> device_surface_nodes_;
  int device_body_vertices_ = 0;  // compact vertices before the obstacles' (append_obstacles)
  double kappa_min_ = 0, kappa_max_ = 0;
  double min_distance_eps2_ = 0;
  ContactStats stats_;
};

template <class F>
bool ContactForm::for_each_pair(F&& f) const {
  const std::size_t count[kNumCandidateKinds] = {vertex_face_.size(),          edge_edge_.size(),
                                                 vertex_plane_.size(),         vertex_obstacle_face_.size(),
                                                 edge_obstacle_edge_.size(),   obstacle_vertex_face_.size()};
  bool ok = true;
  for (int kind = 0; kind < kNumCandidateKinds; ++kind)
    for (std::size_t i = 0; i < count[kind]; ++i) ok = f(static_cast<CandidateKind>(kind), i) && ok;
  return ok;
}

}  // namespace dipc
