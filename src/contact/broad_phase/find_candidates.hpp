// Broad phase of IPC contact (Li et al. 2020, "Incremental Potential Contact", ACM TOG
// 39(4)): the vertex–triangle and edge–edge pairs whose inflated (optionally
// swept) bounding boxes overlap, found with one BVH over the triangles and one over the
// edges in O(n log n), never by testing all pairs.
//
// Proximity candidates: with static boxes (x1 == nullptr) and inflation r, every pair at an
// (unsquared) distance <= 2 r is reported, because the gap between two boxes is at most the
// distance between what they contain; for the squared activation distance d̂ take
// r = sqrt(d̂) / 2. CCD candidates: with x1 = x0 + p the swept boxes contain both
// trajectories, so every pair that can meet along the step is reported.
#pragma once
#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include "contact/broad_phase/broad_phase_error.hpp"
#include "contact/broad_phase/surface_view.hpp"

namespace dipc::contact {

struct Candidates {
  std::vector<std::array<std::int32_t, 2>> vertex_face;  // (vertex id, face id)
  std::vector<std::array<std::int32_t, 2>> edge_edge;    // (edge a, edge b), a < b
};

// Pair filters applied after the box test and the shared-vertex exclusion; an empty
// std::function keeps every pair.
struct CandidateFilter {
  // Called with the groups (SurfaceView::vertex_group) of the pair's first vertices:
  // (group of the vertex, group of the face's vertex 0) and (group of edge a's vertex 0,
  // group of edge b's vertex 0) with a < b, so it should be symmetric. Self-contact off:
  // return group_a != group_b. Requires vertex_group.
  std::function<bool(int group_a, int group_b)> allow_groups;
  // Ownership rules of a distributed run (which rank evaluates a pair) go here.
  std::function<bool(std::int32_t vertex, std::int32_t face)> keep_vertex_face;
  std::function<bool(std::int32_t edge_a, std::int32_t edge_b)> keep_edge_edge;  // a < b
};

// Replaces *out by every vertex–face and edge–edge pair whose boxes overlap (each primitive's
// box at x0, or from x0 to x1, grown by `inflation` on every side; touching boxes overlap),
// except pairs that share a vertex and pairs the filter rejects. Both lists are sorted
// lexicographically and hold no duplicates, so the result does not depend on the traversal.
// Throws BroadPhaseError when out is null, inflation is negative or not finite, a count is
// negative, an array needed for a positive count is null, a vertex id is out of range (names
// the edge or face), a coordinate is not finite (names the vertex), or allow_groups is
// given without vertex_group.
void find_candidates(const SurfaceView& surface, double inflation, Candidates* out, const CandidateFilter& filter);

// The same with only a group filter (`allow(group_a, group_b)`, see CandidateFilter).
void find_candidates(const SurfaceView& surface, double inflation, Candidates* out,
                     const std::function<bool(int, int)>& allow = {});

}  // namespace dipc::contact
