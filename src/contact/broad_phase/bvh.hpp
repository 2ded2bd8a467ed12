// Bounding volume hierarchy over axis-aligned boxes: built top-down by median splits, then
// queried for every box that overlaps a given one. It is the search structure of the contact
// broad phase (find_candidates.hpp): building costs O(n log n) and a query O(log n + k) on
// surface meshes, so a broad phase never tests all pairs.
#pragma once
#include <cstdint>
#include <vector>

#include "contact/broad_phase/aabb.hpp"
#include "contact/broad_phase/broad_phase_error.hpp"

namespace dipc::contact {

class Bvh {
 public:
  Bvh() = default;
  // Builds the hierarchy over boxes[0..n); primitive i is reported as id i. The tree
  // (which ids share a leaf, every node box) depends only on the boxes, not on the
  // standard library: splits are by the median of a total order (centre, then id).
  explicit Bvh(const std::vector<Aabb>& boxes);

  int num_primitives() const { return static_cast<int>(leaf_ids_.size()); }
  // Tree depth (a lone leaf has depth 1): 1 + ceil(log2(ceil(n / kLeafSize))).
  int depth() const { return depth_; }

  // Calls visit(id) once for every primitive whose box overlaps `query` (closed boxes,
  // aabbs_overlap). Ids come in tree order, not sorted.
  template <class Visit>
  void for_each_overlap(const Aabb& query, Visit&& visit) const;

  static constexpr int kLeafSize = 4;
  // Median splits halve the primitive count per level, so 2^31 primitives need a depth of
  // 31; the traversal stack holds at most depth + 1 entries.
  static constexpr int kMaxDepth = 64;

 private:
  struct Node {
    Aabb box;
    // Leaf (count > 0): its primitives are slots [first, first + count) of leaf_ids_.
    // Inner node (count == 0): the left child is the next node, `first` is the right child.
    std::int32_t first = 0;
    std::int32_t count = 0;
  };

  // A primitive during construction: its box centre (times 2) next to its id, so the
  // median selections read contiguous memory.
  struct BuildItem {
    double centre[3];
    std::int32_t id;
  };
  std::int32_t build(std::int32_t begin, std::int32_t end, std::vector<BuildItem>& items,
                     const std::vector<Aabb>& boxes, int level);

  std::vector<Node> nodes_;
  std::vector<std::int32_t> leaf_ids_;  // primitive ids in leaf order
  std::vector<Aabb> leaf_boxes_;        // their boxes, in the same order (contiguous reads)
  int depth_ = 0;
};

template <class Visit>
void Bvh::for_each_overlap(const Aabb& query, Visit&& visit) const {
  if (nodes_.empty()) return;
  std::int32_t stack[kMaxDepth + 1];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const std::int32_t index = stack[--top];
    const Node& node = nodes_[index];
    if (!aabbs_overlap(node.box, query)) continue;
    if (node.count > 0) {
      for (std::int32_t s = node.first; s < node.first + node.count; ++s) {
        if (aabbs_overlap(leaf_boxes_[s], query)) visit(leaf_ids_[s]);
      }
    } else {
      stack[top++] = node.first;
      stack[top++] = index + 1;
    }
  }
}

}  // namespace dipc::contact
