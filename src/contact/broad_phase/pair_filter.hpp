// The pair filters of a distributed contact search as data: which groups (bodies) may touch,
// and which rank evaluates a pair. One host/device formula for both searches: the CPU's
// find_candidates calls these through its CandidateFilter (ContactForm builds it from the
// arrays), and the device broad phase (cuda/device_broad_phase.cu) calls them in its kernels,
// so the two searches keep and drop the same pairs by construction.
//
// The rules (docs/design.md §5.3): a vertex–face pair belongs to the owner of its vertex, an
// edge–edge pair to the owner of the edge with the smaller global id. With triangle-mesh
// obstacles (group −1, which never meets itself): a pair of an obstacle vertex (kFaceDecides)
// belongs to the owner of the body triangle, and an obstacle edge, whose global id is larger
// than any body edge's, leaves a pair to the body edge's owner.
#pragma once
#include <cstdint>

#include "math/host_device.hpp"

namespace dipc::contact {

// owned_vertex's value for a vertex whose vertex–face pairs belong to the face's owner.
constexpr char kFaceDecides = 2;

// Views of the filter arrays (host or device memory, as the caller's search runs).
struct PairFilter {
  // Per vertex, its group (null: no group filter); per group id, whether it may touch itself
  // (ids beyond num_self, and negative ids, may not).
  const std::int32_t* group = nullptr;
  const char* self = nullptr;
  int num_self = 0;
  // Per vertex: owned (1), not (0), or kFaceDecides; per face: owned (read for kFaceDecides
  // vertices only). Null owned_vertex: every vertex–face pair kept.
  const char* owned_vertex = nullptr;
  const char* owned_face = nullptr;
  // Per edge: its global id and whether it is owned. Null edge_gid: every edge–edge pair kept.
  const std::int64_t* edge_gid = nullptr;
  const char* owned_edge = nullptr;
};

// May a primitive of group a meet one of group b? Different groups always may (a body and an
// obstacle too); a group meets itself only where self-contact is on.
DIPC_HD bool groups_may_touch(const PairFilter& f, int a, int b) {
  return a != b || (a >= 0 && a < f.num_self && f.self[a] != 0);
}

// Does this rank evaluate the pair of vertex v and face `face`?
DIPC_HD bool keeps_vertex_face(const PairFilter& f, std::int32_t v, std::int32_t face) {
  if (!f.owned_vertex) return true;
  return f.owned_vertex[v] == kFaceDecides ? f.owned_face[face] != 0 : f.owned_vertex[v] != 0;
}

// Does this rank evaluate the pair of edges a and b?
DIPC_HD bool keeps_edge_edge(const PairFilter& f, std::int32_t a, std::int32_t b) {
  return !f.edge_gid || f.owned_edge[f.edge_gid[a] < f.edge_gid[b] ? a : b] != 0;
}

}  // namespace dipc::contact
