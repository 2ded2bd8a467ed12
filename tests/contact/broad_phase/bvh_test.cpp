// Bvh::for_each_overlap against testing every box, on random boxes of mixed sizes, on
// sizes around the leaf size, and on many identical boxes (all centres tie).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "contact/broad_phase/bvh.hpp"

namespace dipc::contact {
namespace {

std::vector<Aabb> random_boxes(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Aabb> boxes(n);
  for (Aabb& b : boxes) {
    // Mostly small boxes, some long thin ones (up to the whole domain along one axis).
    const int long_axis = unit(rng) < 0.1 ? static_cast<int>(3 * unit(rng)) : -1;
    for (int k = 0; k < 3; ++k) {
      const double c = unit(rng);
      const double half = (k == long_axis ? 0.5 : 0.03) * unit(rng);
      b.lo[k] = c - half;
      b.hi[k] = c + half;
    }
  }
  return boxes;
}

std::vector<std::int32_t> hits_of(const Bvh& bvh, const Aabb& q) {
  std::vector<std::int32_t> hits;
  bvh.for_each_overlap(q, [&](std::int32_t id) { hits.push_back(id); });
  std::sort(hits.begin(), hits.end());
  return hits;
}

std::vector<std::int32_t> brute_hits(const std::vector<Aabb>& boxes, const Aabb& q) {
  std::vector<std::int32_t> hits;
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    bool overlap = true;
    for (int k = 0; k < 3; ++k) overlap = overlap && boxes[i].lo[k] <= q.hi[k] && q.lo[k] <= boxes[i].hi[k];
    if (overlap) hits.push_back(static_cast<std::int32_t>(i));
  }
  return hits;
}

int depth_bound(int n) {
  const int leaves = (n + Bvh::kLeafSize - 1) / Bvh::kLeafSize;
  return 1 + static_cast<int>(std::ceil(std::log2(static_cast<double>(leaves))));
}

TEST(Bvh, EmptyTreeReportsNothing) {
  const Bvh bvh(std::vector<Aabb>{});
  EXPECT_EQ(bvh.num_primitives(), 0);
  EXPECT_TRUE(hits_of(bvh, Aabb{{-1e9, -1e9, -1e9}, {1e9, 1e9, 1e9}}).empty());
}

TEST(Bvh, QueriesMatchTestingEveryBox) {
  for (int n : {1, 3, 4, 5, 9, 17, 1000}) {
    SCOPED_TRACE("n = " + std::to_string(n));
    const std::vector<Aabb> boxes = random_boxes(n, 40 + n);
    const Bvh bvh(boxes);
    EXPECT_EQ(bvh.num_primitives(), n);
    EXPECT_LE(bvh.depth(), depth_bound(n));
    std::size_t total = 0;
    for (const Aabb& q : random_boxes(200, 7 + n)) {
      const std::vector<std::int32_t> hits = hits_of(bvh, q);
      EXPECT_EQ(hits, brute_hits(boxes, q));  // also: every id at most once
      total += hits.size();
    }
    if (n == 1000) {
      EXPECT_GT(total, 0u);
    }
  }
}

TEST(Bvh, IdenticalBoxesStayBalanced) {
  const std::vector<Aabb> boxes(1000, Aabb{{0, 0, 0}, {1, 1, 1}});
  const Bvh bvh(boxes);
  EXPECT_LE(bvh.depth(), depth_bound(1000));
  EXPECT_EQ(hits_of(bvh, Aabb{{1, 1, 1}, {2, 2, 2}}).size(), 1000u);  // touching corner
  EXPECT_TRUE(hits_of(bvh, Aabb{{1.5, 0, 0}, {2, 1, 1}}).empty());
}

}  // namespace
}  // namespace dipc::contact
