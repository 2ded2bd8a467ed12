// Top-down median-split construction of the broad-phase BVH (bvh.hpp).
#include "contact/broad_phase/bvh.hpp"

#include <algorithm>
#include <limits>
#include <string>

namespace dipc::contact {

Bvh::Bvh(const std::vector<Aabb>& boxes) {
  if (boxes.size() > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max())) {
    throw BroadPhaseError("Bvh: " + std::to_string(boxes.size()) + " boxes do not fit in 32-bit primitive ids");
  }
  const auto n = static_cast<std::int32_t>(boxes.size());
  if (n == 0) return;
  std::vector<BuildItem> items(boxes.size());
  for (std::int32_t i = 0; i < n; ++i) {
    for (int k = 0; k < 3; ++k) items[i].centre[k] = boxes[i].lo[k] + boxes[i].hi[k];
    items[i].id = i;
  }
  // Splits stop at kLeafSize, so every leaf holds at least 2 primitives (when n >= 2) and a
  // binary tree with at most n / 2 leaves has fewer than n nodes.
  nodes_.reserve(static_cast<std::size_t>(n));
  build(0, n, items, boxes, 1);
  leaf_ids_.resize(boxes.size());
  leaf_boxes_.resize(boxes.size());
  for (std::int32_t s = 0; s < n; ++s) {
    leaf_ids_[s] = items[s].id;
    leaf_boxes_[s] = boxes[items[s].id];
  }
}

std::int32_t Bvh::build(std::int32_t begin, std::int32_t end, std::vector<BuildItem>& items,
                        const std::vector<Aabb>& boxes, int level) {
  if (level > kMaxDepth) {
    throw BroadPhaseError("Bvh: tree depth exceeds " + std::to_string(kMaxDepth));
  }
  depth_ = std::max(depth_, level);
  const auto index = static_cast<std::int32_t>(nodes_.size());
  nodes_.emplace_back();
  if (end - begin <= kLeafSize) {
    Aabb box = boxes[items[begin].id];
    for (std::int32_t s = begin + 1; s < end; ++s) aabb_merge(&box, boxes[items[s].id]);
    nodes_[index].box = box;
    nodes_[index].first = begin;
    nodes_[index].count = end - begin;
    return index;
  }
  // Split across the axis where the centres spread most, at the median, so both halves
  // are equal and the depth stays logarithmic whatever the geometry (equal centres are
  // ordered by id, which also makes the split unique).
  double lo[3], hi[3];
  for (int k = 0; k < 3; ++k) lo[k] = hi[k] = items[begin].centre[k];
  for (std::int32_t s = begin + 1; s < end; ++s) {
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], items[s].centre[k]);
      hi[k] = std::max(hi[k], items[s].centre[k]);
    }
  }
  int axis = 0;
  for (int k = 1; k < 3; ++k) {
    if (hi[k] - lo[k] > hi[axis] - lo[axis]) axis = k;
  }
  const std::int32_t mid = begin + (end - begin) / 2;
  std::nth_element(items.begin() + begin, items.begin() + mid, items.begin() + end,
                   [axis](const BuildItem& a, const BuildItem& b) {
                     return a.centre[axis] < b.centre[axis] || (a.centre[axis] == b.centre[axis] && a.id < b.id);
                   });
  const std::int32_t left = build(begin, mid, items, boxes, level + 1);
  const std::int32_t right = build(mid, end, items, boxes, level + 1);
  // Children are built first, so the node box is the union of two boxes (O(n) overall).
  Aabb box = nodes_[left].box;
  aabb_merge(&box, nodes_[right].box);
  nodes_[index].box = box;
  nodes_[index].first = right;
  nodes_[index].count = 0;
  return index;
}

}  // namespace dipc::contact
