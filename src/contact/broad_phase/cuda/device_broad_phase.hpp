// The contact broad phase on the CUDA device: the same vertex–triangle and edge–edge candidates
// as contact::find_candidates (find_candidates.hpp) — same boxes, same exclusions, same filters,
// same sorted order — found by a linear BVH built on the device (Karras 2012, "Maximizing
// Parallelism in the Construction of BVHs, Octrees, and k-d Trees"). (Half-space obstacles need
// no search: ContactForm pairs every surface vertex with every plane.)
//
// Plain C++: host code includes this header. The searches live in device_broad_phase.cu, or, in
// builds without CUDA, in device_broad_phase_host.cpp, where they throw dipc::device::DeviceError.
// The surface (connectivity, groups, ownership) is uploaded once per change; positions are
// device arrays; the candidate lists come back to the host once per search (host code needs
// them), everything before that runs on the device.
//
// Filters are data, not callbacks, so that kernels can apply them: the arrays of
// contact/broad_phase/pair_filter.hpp, whose host/device functions (groups_may_touch,
// keeps_vertex_face, keeps_edge_edge; each applied only when its arrays are given) the kernels
// call. With the same data, find_candidates gives what contact::find_candidates gives with a
// CandidateFilter calling those functions, as ContactForm's host search does. ContactForm
// appends triangle-mesh obstacles in group −1 (pair_filter.hpp states the ownership rules).
//
// Vertices may also follow a prescribed segment of their own instead of rows of x and p (the
// obstacles' vertices, whose positions are functions of time): see vertex_node.
#pragma once
#include <cstdint>
#include <memory>
#include <vector>

#include "contact/broad_phase/find_candidates.hpp"
#include "contact/broad_phase/pair_filter.hpp"
#include "device/device_runtime.hpp"

namespace dipc::device {

// A surface as the device broad phase needs it, on the host (for upload). Vertex ids index the
// position arrays: 3 doubles per vertex.
struct BroadPhaseSurface {
  int num_vertices = 0;
  std::vector<std::int32_t> edges;  // 2 vertex ids per edge
  std::vector<std::int32_t> faces;  // 3 vertex ids per triangle
  // Group filter: a group per vertex (empty: no group filter) and, per group id, whether a
  // group may touch itself (ids beyond the list may not).
  std::vector<std::int32_t> vertex_group;
  std::vector<char> self_contact;
  // Ownership filters: per vertex (empty: every vertex–face pair kept; kFaceDecides: the
  // face's owned_face flag decides), per face (needed only where a vertex is kFaceDecides);
  // per edge a global id and an owned flag (both empty: every edge–edge pair kept).
  std::vector<char> owned_vertex;
  std::vector<char> owned_face;
  std::vector<std::int64_t> edge_gid;
  std::vector<char> owned_edge;
  // Per vertex, its row in the node arrays x and p of find_candidates_on_segment, or, as
  // −2 − k, row k of that search's prescribed positions (empty: that search is not available).
  std::vector<std::int32_t> vertex_node;
};

using contact::kFaceDecides;  // owned_vertex's value: the face's owner decides (pair_filter.hpp)

// Positions of the vertices that follow a prescribed segment (vertex_node −2 − k: row k),
// from start to end (device arrays, 3 doubles per row); moving: whether start and end differ
// anywhere (when neither they nor p move any vertex, the search takes static boxes).
struct PrescribedVertices {
  const double* start = nullptr;
  const double* end = nullptr;
  bool moving = false;
};

class DeviceBroadPhase {
 public:
  DeviceBroadPhase();
  ~DeviceBroadPhase();
  DeviceBroadPhase(DeviceBroadPhase&&) noexcept;
  DeviceBroadPhase& operator=(DeviceBroadPhase&&) noexcept;

  // Copies the surface to the device; call again whenever the primitives change. Throws
  // contact::BroadPhaseError as contact::find_candidates does for a negative vertex count or a
  // vertex id out of range (same message), for per-vertex, per-edge or per-face arrays of the
  // wrong length, and for kFaceDecides vertices without owned_face.
  void upload(const BroadPhaseSurface& surface);

  // contact::find_candidates on the uploaded surface at device positions x0 and, when not null,
  // x1 (3 doubles per vertex each), with the filters of the uploaded data: the same lists in
  // the same order. Throws contact::BroadPhaseError as contact::find_candidates does when out
  // is null, the inflation is negative or not finite, x0 is null for a positive vertex count,
  // or a coordinate is not finite (naming the same vertex and coordinate).
  void find_candidates(const double* x0, const double* x1, double inflation, contact::Candidates* out);

  // The same on a segment of node arrays x + αp, α ∈ [0, 1] (device arrays, 3 per node, rows
  // from vertex_node): x0 = x and x1 = x + p gathered per vertex (for prescribed vertices
  // their start and end), or static boxes at x0 when p is zero at every vertex of the surface
  // and the prescribed vertices do not move, as ContactForm forms them on the host. Throws
  // contact::BroadPhaseError when the surface has prescribed vertices and `prescribed` lacks
  // their positions.
  void find_candidates_on_segment(const double* x, const double* p, double inflation, contact::Candidates* out,
                                  const PrescribedVertices& prescribed = {});

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace dipc::device
