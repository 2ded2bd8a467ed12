// The kinds of barrier pair, by what a pair's stacked positions X hold (contact_pair_terms.hpp):
// vertex–triangle X = [v, t0, t1, t2], edge–edge X = [ea0, ea1, eb0, eb1], vertex–plane X = [v]
// (the plane's point and normal passed beside X). Body–obstacle pairs are of the first two
// kinds, with obstacle vertices among the nodes (obstacle_nodes.hpp). The values are stored in
// device pair lists (cuda/contact_kernels.hpp) as 32-bit integers.
#pragma once
#include <cstdint>

#include "math/host_device.hpp"

namespace dipc {

enum class PairKind : std::int32_t { vertex_triangle = 0, edge_edge = 1, vertex_plane = 2 };
constexpr int kNumPairKinds = 3;

// Number of nodes a pair of this kind stacks in X (3 coordinates each).
DIPC_HD int pair_node_count(PairKind kind) { return kind == PairKind::vertex_plane ? 1 : 4; }

// The candidate lists ContactSet (distributed/contact_set.hpp) keeps, in the order its
// for_each_pair visits them, the per-step contact counts report them (ContactForm::
// pair_kind_name) and build_candidate_pairs (cuda/contact_kernels.hpp) reads them:
// vertex–triangle, edge–edge, vertex–plane (bodies and planes), then body vertex–obstacle
// triangle, body edge–obstacle edge, obstacle vertex–body triangle. Each list's pairs are of
// one PairKind.
enum class CandidateKind : int {
  vertex_face = 0,
  edge_edge = 1,
  vertex_plane = 2,
  vertex_obstacle_face = 3,
  edge_obstacle_edge = 4,
  obstacle_vertex_face = 5
};
constexpr int kNumCandidateKinds = 6;

}  // namespace dipc
