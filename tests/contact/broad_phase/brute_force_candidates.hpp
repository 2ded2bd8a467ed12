// Reference broad phase for the tests: every vertex–face and edge–edge pair tested, O(n^2),
// written independently of the library's box code (only the filter struct is shared).
#pragma once
#include <algorithm>
#include <array>
#include <cstdint>

#include "contact/broad_phase/find_candidates.hpp"
#include "test_surfaces.hpp"

namespace dipc::contact::testing {

struct ReferenceBox {
  double lo[3];
  double hi[3];
};

inline ReferenceBox reference_box(const TestSurface& s, const std::int32_t* ids, int count, double inflation) {
  ReferenceBox b;
  for (int k = 0; k < 3; ++k) {
    b.lo[k] = s.x0[3 * ids[0] + k];
    b.hi[k] = s.x0[3 * ids[0] + k];
  }
  for (int i = 0; i < count; ++i) {
    for (int k = 0; k < 3; ++k) {
      b.lo[k] = std::min(b.lo[k], s.x0[3 * ids[i] + k]);
      b.hi[k] = std::max(b.hi[k], s.x0[3 * ids[i] + k]);
      if (!s.x1.empty()) {
        b.lo[k] = std::min(b.lo[k], s.x1[3 * ids[i] + k]);
        b.hi[k] = std::max(b.hi[k], s.x1[3 * ids[i] + k]);
      }
    }
  }
  for (int k = 0; k < 3; ++k) {
    b.lo[k] -= inflation;
    b.hi[k] += inflation;
  }
  return b;
}

inline bool reference_overlap(const ReferenceBox& a, const ReferenceBox& b) {
  for (int k = 0; k < 3; ++k) {
    if (a.hi[k] < b.lo[k] || b.hi[k] < a.lo[k]) return false;
  }
  return true;
}

inline Candidates brute_force_candidates(const TestSurface& s, double inflation, const CandidateFilter& filter = {}) {
  Candidates out;
  const int nv = s.num_vertices();
  const int nf = static_cast<int>(s.faces.size() / 3);
  const int ne = static_cast<int>(s.edges.size() / 2);
  for (std::int32_t v = 0; v < nv; ++v) {
    const ReferenceBox bv = reference_box(s, &v, 1, inflation);
    for (std::int32_t f = 0; f < nf; ++f) {
      const std::int32_t* t = &s.faces[3 * f];
      if (t[0] == v || t[1] == v || t[2] == v) continue;
      if (!reference_overlap(bv, reference_box(s, t, 3, inflation))) continue;
      if (filter.allow_groups && !filter.allow_groups(s.groups[v], s.groups[t[0]])) continue;
      if (filter.keep_vertex_face && !filter.keep_vertex_face(v, f)) continue;
      out.vertex_face.push_back({v, f});
    }
  }
  for (std::int32_t a = 0; a < ne; ++a) {
    const std::int32_t* ea = &s.edges[2 * a];
    const ReferenceBox ba = reference_box(s, ea, 2, inflation);
    for (std::int32_t b = a + 1; b < ne; ++b) {
      const std::int32_t* eb = &s.edges[2 * b];
      if (ea[0] == eb[0] || ea[0] == eb[1] || ea[1] == eb[0] || ea[1] == eb[1]) continue;
      if (!reference_overlap(ba, reference_box(s, eb, 2, inflation))) continue;
      if (filter.allow_groups && !filter.allow_groups(s.groups[ea[0]], s.groups[eb[0]])) continue;
      if (filter.keep_edge_edge && !filter.keep_edge_edge(a, b)) continue;
      out.edge_edge.push_back({a, b});
    }
  }
  return out;
}

}  // namespace dipc::contact::testing
