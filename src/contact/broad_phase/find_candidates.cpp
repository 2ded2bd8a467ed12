// Broad phase (find_candidates.hpp): input checks, one BVH over the triangles queried by every
// vertex and one over the edges queried by every edge.
#include "contact/broad_phase/find_candidates.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "contact/broad_phase/aabb.hpp"
#include "contact/broad_phase/bvh.hpp"

namespace dipc::contact {
namespace {

void check_ids(const std::int32_t* ids, int count, int per, int num_vertices, const char* kind) {
  for (int e = 0; e < count; ++e) {
    for (int j = 0; j < per; ++j) {
      const std::int32_t v = ids[static_cast<std::int64_t>(per) * e + j];
      if (v < 0 || v >= num_vertices) {
        throw BroadPhaseError("find_candidates: " + std::string(kind) + " " + std::to_string(e) + " vertex " +
                              std::to_string(j) + " = " + std::to_string(v) + " is outside [0, " +
                              std::to_string(num_vertices) + ")");
      }
    }
  }
}

void check_finite(const double* x, int num_vertices, const char* name) {
  for (int v = 0; v < num_vertices; ++v) {
    for (int k = 0; k < 3; ++k) {
      if (!std::isfinite(x[3 * static_cast<std::int64_t>(v) + k])) {
        throw BroadPhaseError("find_candidates: vertex " + std::to_string(v) + " has a non-finite " + name +
                              " coordinate " + std::to_string(k));
      }
    }
  }
}

void check_input(const SurfaceView& s, double inflation, const Candidates* out, const CandidateFilter& filter) {
  if (out == nullptr) throw BroadPhaseError("find_candidates: output is null");
  if (!std::isfinite(inflation) || inflation < 0.0) {
    throw BroadPhaseError("find_candidates: inflation " + std::to_string(inflation) + " must be finite and >= 0");
  }
  if (s.num_vertices < 0 || s.num_edges < 0 || s.num_faces < 0) {
    throw BroadPhaseError("find_candidates: negative count (vertices " + std::to_string(s.num_vertices) + ", edges " +
                          std::to_string(s.num_edges) + ", faces " + std::to_string(s.num_faces) + ")");
  }
  if (s.num_vertices > 0 && s.x0 == nullptr) {
    throw BroadPhaseError("find_candidates: x0 is null for " + std::to_string(s.num_vertices) + " vertices");
  }
  if (s.num_edges > 0 && s.edges == nullptr) {
    throw BroadPhaseError("find_candidates: edges is null for " + std::to_string(s.num_edges) + " edges");
  }
  if (s.num_faces > 0 && s.faces == nullptr) {
    throw BroadPhaseError("find_candidates: faces is null for " + std::to_string(s.num_faces) + " faces");
  }
  if (filter.allow_groups && s.vertex_group == nullptr && s.num_vertices > 0) {
    throw BroadPhaseError("find_candidates: a group filter needs SurfaceView::vertex_group");
  }
  check_ids(s.edges, s.num_edges, 2, s.num_vertices, "edge");
  check_ids(s.faces, s.num_faces, 3, s.num_vertices, "face");
  if (s.num_vertices > 0) check_finite(s.x0, s.num_vertices, "x0");
  if (s.num_vertices > 0 && s.x1 != nullptr) check_finite(s.x1, s.num_vertices, "x1");
}

std::vector<Aabb> primitive_boxes(const SurfaceView& s, const std::int32_t* ids, int count, int per, double inflation) {
  std::vector<Aabb> boxes(static_cast<std::size_t>(count));
  for (int e = 0; e < count; ++e) {
    boxes[e] = primitive_box(s.x0, s.x1, ids + static_cast<std::int64_t>(per) * e, per, inflation);
  }
  return boxes;
}

// Pairs that share a vertex are excluded: they are at distance zero by construction, so they
// are no contact and the barrier would be infinite on them (IPC Toolkit skips them too).
bool face_has_vertex(const std::int32_t* tri, std::int32_t v) { return tri[0] == v || tri[1] == v || tri[2] == v; }

bool edges_share_vertex(const std::int32_t* a, const std::int32_t* b) {
  return a[0] == b[0] || a[0] == b[1] || a[1] == b[0] || a[1] == b[1];
}

void find_vertex_face(const SurfaceView& s, double inflation, const CandidateFilter& filter,
                      std::vector<std::array<std::int32_t, 2>>* pairs) {
  if (s.num_vertices == 0 || s.num_faces == 0) return;
  const Bvh faces(primitive_boxes(s, s.faces, s.num_faces, 3, inflation));
  std::vector<std::int32_t> hits;
  for (std::int32_t v = 0; v < s.num_vertices; ++v) {
    const Aabb query = primitive_box(s.x0, s.x1, &v, 1, inflation);
    hits.clear();
    faces.for_each_overlap(query, [&](std::int32_t f) {
      const std::int32_t* tri = s.faces + 3 * static_cast<std::int64_t>(f);
      if (face_has_vertex(tri, v)) return;
      if (filter.allow_groups && !filter.allow_groups(s.vertex_group[v], s.vertex_group[tri[0]])) {
        return;
      }
      if (filter.keep_vertex_face && !filter.keep_vertex_face(v, f)) return;
      hits.push_back(f);
    });
    // Vertices are visited in order, so sorting each vertex's faces sorts the whole list.
    std::sort(hits.begin(), hits.end());
    for (const std::int32_t f : hits) pairs->push_back({v, f});
  }
}

void find_edge_edge(const SurfaceView& s, double inflation, const CandidateFilter& filter,
                    std::vector<std::array<std::int32_t, 2>>* pairs) {
  if (s.num_edges < 2) return;
  const std::vector<Aabb> boxes = primitive_boxes(s, s.edges, s.num_edges, 2, inflation);
  const Bvh edges(boxes);
  std::vector<std::int32_t> hits;
  for (std::int32_t a = 0; a < s.num_edges; ++a) {
    const std::int32_t* ea = s.edges + 2 * static_cast<std::int64_t>(a);
    hits.clear();
    edges.for_each_overlap(boxes[a], [&](std::int32_t b) {
      if (b <= a) return;  // each unordered pair once, from its smaller edge
      const std::int32_t* eb = s.edges + 2 * static_cast<std::int64_t>(b);
      if (edges_share_vertex(ea, eb)) return;
      if (filter.allow_groups && !filter.allow_groups(s.vertex_group[ea[0]], s.vertex_group[eb[0]])) {
        return;
      }
      if (filter.keep_edge_edge && !filter.keep_edge_edge(a, b)) return;
      hits.push_back(b);
    });
    std::sort(hits.begin(), hits.end());
    for (const std::int32_t b : hits) pairs->push_back({a, b});
  }
}

}  // namespace

void find_candidates(const SurfaceView& surface, double inflation, Candidates* out, const CandidateFilter& filter) {
  check_input(surface, inflation, out, filter);
  out->vertex_face.clear();
  out->edge_edge.clear();
  find_vertex_face(surface, inflation, filter, &out->vertex_face);
  find_edge_edge(surface, inflation, filter, &out->edge_edge);
}

void find_candidates(const SurfaceView& surface, double inflation, Candidates* out,
                     const std::function<bool(int, int)>& allow) {
  CandidateFilter filter;
  filter.allow_groups = allow;
  find_candidates(surface, inflation, out, filter);
}

}  // namespace dipc::contact
