// The contact barrier and its CCD on the CUDA device: a pair list in device memory (structure
// of arrays) and the passes over it — energy, gradient, Hessian values in COO order, active
// flags, minimum distance, minimum time of impact — each calling the point functions of
// contact/contact_pair_terms.hpp that ContactForm's CPU loops call.
//
// Plain C++: host code includes this header. The passes live in contact_kernels.cu, or, in
// builds without CUDA, in contact_kernels_host.cpp, where they throw dipc::device::DeviceError;
// the host lists and uploads in contact_pair_list.cpp. Node positions x, directions p,
// gradients g and Hessian values are device pointers (3 values per ext-local node, as
// ContactForm numbers them); pair lists and obstacles are uploaded from the host. Pairs with
// triangle-mesh obstacles name the obstacle's vertices by node id −2 − k (obstacle_nodes.hpp):
// their positions come from DeviceContactObstacles, and they get no gradient or Hessian entries.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "contact/pair_kind.hpp"
#include "device/device_runtime.hpp"

namespace dipc::device {

// A contact pair list on the host, in the order the device list keeps: pair i has kind[i]
// (pair_kind.hpp), ext-local nodes nodes[4i..4i+3] (unused slots −1, obstacle vertices −2 − k),
// weight w_i, mollifier threshold eps_x[i] (edge–edge) and plane[i] (vertex–plane: index into
// the planes, −1 otherwise).
struct ContactPairList {
  std::vector<PairKind> kind;
  std::vector<std::int32_t> nodes;
  std::vector<double> weight, eps_x;
  std::vector<std::int32_t> plane;

  std::size_t size() const { return kind.size(); }
  void clear();
  void add(PairKind pair_kind, const std::int32_t pair_nodes[4], double pair_weight, double pair_eps_x, int pair_plane);
  // n pairs, to be written with set() (each pair its own slot, e.g. from several threads).
  void resize(std::size_t n);
  void set(std::size_t i, PairKind pair_kind, const std::int32_t pair_nodes[4], double pair_weight, double pair_eps_x,
           int pair_plane);
  bool operator==(const ContactPairList& o) const;
  bool operator!=(const ContactPairList& o) const { return !(*this == o); }
};

// The same list in device memory. Nodes are stored slot-major (node k of pair i at
// nodes[k·n + i]) so that neighbouring threads read neighbouring words. hessian_offset[i] is
// the first COO value of pair i when the list is a Hessian pattern: a pair takes (3 b)² values,
// b the number of its body nodes (4 for body pairs, 1 for vertex–plane pairs, 1 to 3 for pairs
// with an obstacle: the body nodes' block, as ContactForm's COO pattern), one after the other.
struct DeviceContactPairs {
  Array<std::int32_t> kind{"contact pair kinds"};  // PairKind values
  Array<std::int32_t> nodes{"contact pair nodes"};
  Array<double> weight{"contact pair weights"};
  Array<double> eps_x{"contact pair mollifier thresholds"};
  Array<std::int32_t> plane{"contact pair planes"};
  Array<std::size_t> hessian_offset{"contact Hessian offsets"};
  std::size_t count = 0;
  std::size_t hessian_values = 0;  // total number of COO values of the list

  void upload(const ContactPairList& pairs);
};

// What ContactSet::describe builds a candidate pair from, in device memory, so that the
// candidate list is built there from the pairs' indices alone (build_candidate_pairs): the
// body's triangles and edges known on the rank (ext-local nodes, owned then ghost), the edges'
// global ids, squared rest lengths and weights (the mean rest area of the end vertices: set for
// the rank's own edges, NaN for ghosts, which never decide a pair's weight), the rest areas of
// the rank's surface vertices (per mesh-local node, NaN elsewhere), and the triangle-mesh
// obstacles' triangles and edges (obstacle vertex ids), squared edge rest lengths and vertex
// areas. The body's part is uploaded whenever an exchange changes the ghost surface.
struct DevicePairSources {
  Array<std::int32_t> face_nodes{"contact triangle nodes"};  // 3 per triangle
  Array<std::int32_t> edge_nodes{"contact edge nodes"};      // 2 per edge
  Array<std::int64_t> edge_gid{"contact edge ids"};
  Array<double> edge_rest2{"contact edge rest lengths"};
  Array<double> edge_weight{"contact edge weights"};
  Array<double> vertex_area{"contact vertex areas"};
  Array<std::int32_t> obstacle_face_nodes{"obstacle triangle vertices"};  // 3 per triangle
  Array<std::int32_t> obstacle_edge_nodes{"obstacle edge vertices"};      // 2 per edge
  Array<double> obstacle_edge_rest2{"obstacle edge rest lengths"};
  Array<double> obstacle_vertex_area{"obstacle vertex areas"};
};

// out = the candidate pairs in ContactSet's order, as DeviceContactPairs::upload of the list
// ContactForm::candidate_pair_list builds on the host would make it (bit for bit, hessian
// offsets included). index (device, 2 per pair) holds each pair's two list entries, the pairs
// of CandidateKind k (pair_kind.hpp) in slots [first[k], first[k + 1]): (vertex node, triangle),
// (edge, edge), (vertex node, plane), (vertex node, obstacle triangle), (edge, obstacle edge),
// (obstacle vertex, triangle).
void build_candidate_pairs(const DevicePairSources& sources, const Array<std::int32_t>& index,
                           const std::array<std::size_t, kNumCandidateKinds + 1>& first, DeviceContactPairs* out);

// The obstacles that pairs refer to. Half-space obstacles: 3 doubles of point and of unit
// normal per plane (a pair's plane[i] indexes them). Triangle-mesh obstacles: the positions of
// their vertices (3 doubles per vertex, vertex k named −2 − k by pairs) at the start and at the
// end of the current segment; evaluations see the end positions, the CCD moves each vertex
// linearly from start to end (ContactForm::gather_segment, the same on the CPU).
struct DeviceContactObstacles {
  Array<double> point{"contact plane points"};
  Array<double> normal{"contact plane normals"};
  Array<double> vertex_start{"obstacle vertex start positions"};
  Array<double> vertex_end{"obstacle vertex end positions"};

  void upload_planes(const std::vector<double>& points, const std::vector<double>& normals);
  void upload_vertices(const std::vector<double>& start, const std::vector<double>& end);
};

// The barrier's constants: squared activation distance d̂², stiffness κ, and whether pair
// Hessians are projected onto the PSD cone.
struct BarrierConstants {
  double dhat2 = 0;
  double kappa = 0;
  bool project = true;
};

// Σ_i κ w_i m_i b(d_i) at x (obstacle vertices at their end positions), summed per block and then over blocks in a fixed order (the
// result does not depend on scheduling). Returns false if a pair is not admissible (d ≤ 0 or
// a vertex on or behind its plane); such pairs add nothing, as on the CPU.
bool contact_barrier_energy(const DeviceContactPairs& pairs, const DeviceContactObstacles& obstacles,
                            const BarrierConstants& c, const double* x, Reducer& reducer, double* energy);
// Adds the barrier gradient into g (atomics; body nodes only). Returns false as
// contact_barrier_energy.
bool add_contact_barrier_gradient(const DeviceContactPairs& pairs, const DeviceContactObstacles& obstacles,
                                  const BarrierConstants& c, const double* x, double* g, Reducer& reducer);
// Writes every pair's Hessian (PSD-projected when c.project; its body nodes' block) at
// values + hessian_offset[i]; inactive and inadmissible pairs write zeros. Returns false as contact_barrier_energy.
bool contact_barrier_hessian(const DeviceContactPairs& pairs, const DeviceContactObstacles& obstacles,
                             const BarrierConstants& c, const double* x, double* values, Reducer& reducer);
// active[i] = 1 if pair i is active at x (0 < d < d̂²), else 0 (active: device array, one per
// pair). Returns false as contact_barrier_energy.
bool contact_active_flags(const DeviceContactPairs& pairs, const DeviceContactObstacles& obstacles,
                          const BarrierConstants& c, const double* x, std::int32_t* active, Reducer& reducer);
// Smallest squared distance over the pairs at x (contact_pair_squared_distance); +∞ without
// pairs.
double contact_min_squared_distance(const DeviceContactPairs& pairs, const DeviceContactObstacles& obstacles,
                                    const double* x, Reducer& reducer);
// toi[i] = time of impact of pair i along x + t p (obstacle vertices from their start to their
// end positions), searched on [0, t_max]
// (contact_pair_time_of_impact, bit-identical to the CPU: no fused multiply-add); toi is a
// device array with one entry per pair.
void contact_times_of_impact(const DeviceContactPairs& pairs, const DeviceContactObstacles& obstacles, const double* x,
                             const double* p, double t_max, double* toi);
// Smallest time of impact over the pairs along x + t p, t ∈ [0, t_max], each pair searched on
// [0, t_max] as contact_times_of_impact; t_max without pairs.
double contact_min_time_of_impact(const DeviceContactPairs& pairs, const DeviceContactObstacles& obstacles,
                                  const double* x, const double* p, double t_max, Reducer& reducer);

}  // namespace dipc::device
