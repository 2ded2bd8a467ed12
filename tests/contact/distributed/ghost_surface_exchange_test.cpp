// exchange_ghost_surface under MPI (1, 2 and 3 ranks): a rank receives the records of other
// ranks whose boxes reach its own boxes (touching boxes count), never its own, nothing when it
// owns no primitive, not what lies between two distant parts of its surface, sorted edges first
// and then by global id, with every field as sent; on random boxes, every record that reaches
// one of its boxes and none that misses their union.
#include "contact/distributed/ghost_surface_exchange.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

#include "threads/host_threads.hpp"

namespace dipc {
namespace {

Aabb box(double x0, double x1) { return {{x0, 0, 0}, {x1, 1, 1}}; }

SurfacePrimitiveRecord record(bool face, std::int64_t gid, int rank) {
  SurfacePrimitiveRecord r;
  r.is_face = face ? 1 : 0;
  r.gid = gid;
  r.body = rank + 7;
  r.node = {10 * gid, 10 * gid + 1, face ? 10 * gid + 2 : -1};
  r.rest_length2 = face ? 0.0 : 0.25 * static_cast<double>(gid);
  return r;
}

void expect_same(const SurfacePrimitiveRecord& a, const SurfacePrimitiveRecord& b) {
  EXPECT_EQ(a.is_face, b.is_face);
  EXPECT_EQ(a.gid, b.gid);
  EXPECT_EQ(a.body, b.body);
  EXPECT_EQ(a.node, b.node);
  EXPECT_EQ(a.rest_length2, b.rest_length2);
}

// Rank r's surface fills the cell [r, r + 1] in x. Its primitives: one well inside (reaches
// no other rank), a triangle touching the next cell and an edge touching the previous one.
TEST(GhostSurfaceExchange, SendsWhatReachesAnotherRanksSurface) {
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  auto owned_of = [](int r) {
    return std::vector<SurfacePrimitiveRecord>{record(false, 100 * r + 1, r), record(true, 100 * r + 2, r),
                                               record(false, 100 * r + 3, r)};
  };
  const std::vector<Aabb> boxes{box(rank + 0.1, rank + 0.9), box(rank + 0.9, rank + 1.0), box(rank, rank + 0.05)};
  const std::vector<SurfacePrimitiveRecord> got = exchange_ghost_surface(MPI_COMM_WORLD, owned_of(rank), boxes);

  std::vector<SurfacePrimitiveRecord> expected;  // edges first: the next rank's edge, then the previous rank's triangle
  if (rank + 1 < size) expected.push_back(owned_of(rank + 1)[2]);
  if (rank > 0) expected.push_back(owned_of(rank - 1)[1]);
  ASSERT_EQ(got.size(), expected.size());
  for (std::size_t i = 0; i < got.size(); ++i) expect_same(got[i], expected[i]);
}

// The last rank owns nothing: it receives nothing, even from a box that covers everything,
// and the other ranks receive that box's record from rank 0 (except rank 0 itself).
TEST(GhostSurfaceExchange, RankWithoutSurfaceReceivesNothing) {
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  std::vector<SurfacePrimitiveRecord> owned;
  std::vector<Aabb> boxes;
  if (rank == 0) {
    // Sorted output: gids out of order on purpose (faces after edges, each by gid).
    owned = {record(true, 9, 0), record(false, 5, 0), record(false, 2, 0)};
    boxes = {box(-10, 10), box(-10, 10), box(-10, 10)};
  } else if (rank + 1 < size) {
    owned = {record(true, 1000 + rank, rank)};
    boxes = {box(rank, rank + 1)};
  }
  const std::vector<SurfacePrimitiveRecord> got = exchange_ghost_surface(MPI_COMM_WORLD, owned, boxes);
  if (rank == 0 || rank + 1 == size) {
    // Rank 0 on several ranks receives the middle ranks' triangles (their boxes lie in its
    // reach); alone, or as the rank without surface, nothing.
    const std::size_t middle = size > 2 ? static_cast<std::size_t>(size - 2) : 0;
    ASSERT_EQ(got.size(), rank == 0 ? middle : 0u);
    for (std::size_t i = 0; i < got.size(); ++i) expect_same(got[i], record(true, 1001 + static_cast<int>(i), 1 + i));
    return;
  }
  ASSERT_EQ(got.size(), 3u);
  expect_same(got[0], record(false, 2, 0));
  expect_same(got[1], record(false, 5, 0));
  expect_same(got[2], record(true, 9, 0));
}

// Every rank owns two distant parts, x in [0, 1] and [9, 10] (y, z in [0, 1]); the ranks other
// than 0 also own a primitive between them, x in [4, 5]. Those middles lie inside rank 0's
// surface box but far from its parts: rank 0 receives the others' parts and none of their
// middles; every other rank receives everything of the others (its own middle meets theirs).
TEST(GhostSurfaceExchange, NothingFromBetweenTwoDistantParts) {
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  auto boxes_of = [](int r) {
    std::vector<Aabb> b{{{0, 0, 0}, {1, 1, 1}}, {{9, 0, 0}, {10, 1, 1}}};
    if (r > 0) b.push_back({{4, 0, 0}, {5, 1, 1}});  // between rank 0's parts
    return b;
  };
  auto owned_of = [&](int r) {
    std::vector<SurfacePrimitiveRecord> o;
    for (std::size_t i = 0; i < boxes_of(r).size(); ++i) o.push_back(record(true, 100 * r + static_cast<int>(i), r));
    return o;
  };
  const std::vector<SurfacePrimitiveRecord> got = exchange_ghost_surface(MPI_COMM_WORLD, owned_of(rank), boxes_of(rank));
  std::vector<std::int64_t> expected;
  for (int r = 0; r < size; ++r) {
    if (r == rank) continue;
    for (std::size_t i = 0; i < boxes_of(r).size(); ++i)
      if (rank > 0 || i < 2) expected.push_back(100 * r + static_cast<int>(i));
  }
  std::sort(expected.begin(), expected.end());
  std::vector<std::int64_t> gids;
  for (const SurfacePrimitiveRecord& r : got) gids.push_back(r.gid);
  EXPECT_EQ(gids, expected);
}

// Random boxes on every rank, on 1 and 3 host threads: a rank receives every record of another
// rank whose box overlaps one of its own boxes, and none whose box misses their union.
TEST(GhostSurfaceExchange, RandomBoxesMissNothing) {
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  auto boxes_of = [](int r) {
    std::mt19937_64 rng(17 + r);
    std::uniform_real_distribution<double> at(0, 10), length(0.01, 0.5);
    std::vector<Aabb> b(3000);
    for (Aabb& box : b)
      for (int k = 0; k < 3; ++k) {
        // Each rank's boxes cluster in a few blobs, so that its reach has holes.
        box.lo[k] = std::fmod(at(rng), 2.5) + 2.5 * ((r + k) % 4);
        box.hi[k] = box.lo[k] + length(rng);
      }
    return b;
  };
  for (int threads : {1, 3}) {
    set_host_threads(threads, 1);
    const std::vector<Aabb> mine = boxes_of(rank);
    std::vector<SurfacePrimitiveRecord> owned;
    for (std::size_t i = 0; i < mine.size(); ++i) owned.push_back(record(true, 100000 * rank + static_cast<int>(i), rank));
    const std::vector<SurfacePrimitiveRecord> got = exchange_ghost_surface(MPI_COMM_WORLD, owned, mine);
    Aabb all = aabb_empty();
    for (const Aabb& b : mine) aabb_merge(&all, b);
    std::vector<std::int64_t> gids, must;
    for (const SurfacePrimitiveRecord& r : got) gids.push_back(r.gid);
    for (int r = 0; r < size; ++r) {
      if (r == rank) continue;
      const std::vector<Aabb> theirs = boxes_of(r);
      for (std::size_t i = 0; i < theirs.size(); ++i) {
        const std::int64_t gid = 100000 * r + static_cast<int>(i);
        const bool arrived = std::binary_search(gids.begin(), gids.end(), gid);
        if (!aabbs_overlap(theirs[i], all)) {
          EXPECT_FALSE(arrived) << "box " << gid << " misses rank " << rank;
        }
        bool reaches = false;
        for (const Aabb& b : mine) reaches = reaches || aabbs_overlap(theirs[i], b);
        if (reaches) {
          EXPECT_TRUE(arrived) << "box " << gid << " reaches rank " << rank << " but did not arrive";
        }
      }
    }
  }
  set_host_threads(1);
}

}  // namespace
}  // namespace dipc
