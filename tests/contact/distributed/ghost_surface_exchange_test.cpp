// exchange_ghost_surface under MPI (1, 2 and 3 ranks): a rank receives exactly the records of
// other ranks whose boxes reach the union of its own boxes (touching boxes count), never its
// own, nothing when it owns no primitive, sorted edges first and then by global id, with every
// field as sent.
#include "contact/distributed/ghost_surface_exchange.hpp"

#include <gtest/gtest.h>

#include <vector>

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

}  // namespace
}  // namespace dipc
