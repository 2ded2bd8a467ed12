// find_candidates against the O(n^2) reference on random soups and on a subdivided cube's
// boundary, with static and swept boxes and several inflations.
#include <gtest/gtest.h>

#include <string>

#include "brute_force_candidates.hpp"
#include "contact/broad_phase/find_candidates.hpp"

namespace dipc::contact {
namespace {

using testing::brute_force_candidates;
using testing::TestSurface;

// Compares with the reference and checks the case is not vacuous: some pairs survive, and
// not every pair does (the inflation or the motion would otherwise make the test trivial).
void expect_matches_reference(const TestSurface& s, double inflation, const std::string& label) {
  SCOPED_TRACE(label + ", inflation " + std::to_string(inflation));
  Candidates got;
  find_candidates(s.view(), inflation, &got);
  const Candidates want = brute_force_candidates(s, inflation);
  EXPECT_EQ(got.vertex_face, want.vertex_face);
  EXPECT_EQ(got.edge_edge, want.edge_edge);
  const std::size_t nv = s.x0.size() / 3, nf = s.faces.size() / 3, ne = s.edges.size() / 2;
  EXPECT_GT(want.vertex_face.size(), 0u);
  EXPECT_GT(want.edge_edge.size(), 0u);
  EXPECT_LT(want.vertex_face.size(), nv * nf / 2);
  EXPECT_LT(want.edge_edge.size(), ne * (ne - 1) / 4);
}

TEST(FindCandidates, RandomSoupsStaticMatchBruteForce) {
  for (unsigned seed : {1u, 2u, 3u}) {
    const TestSurface s = testing::random_soup(seed, 6, 300, 40);
    for (double r : {0.0, 1e-3, 0.02, 0.08}) {
      expect_matches_reference(s, r, "soup seed " + std::to_string(seed) + " static");
    }
  }
}

TEST(FindCandidates, RandomSoupsSweptMatchBruteForce) {
  for (unsigned seed : {4u, 5u, 6u}) {
    TestSurface s = testing::random_soup(seed, 6, 300, 40);
    s.x1 = testing::randomly_moved(s.x0, 0.1, seed + 100);
    for (double r : {0.0, 1e-3, 0.02}) {
      expect_matches_reference(s, r, "soup seed " + std::to_string(seed) + " swept");
    }
  }
}

TEST(FindCandidates, CubeBoundaryStaticMatchesBruteForce) {
  const TestSurface s = testing::cube_boundary(8, 1.0, {0.0, 0.0, 0.0});
  // 0: boxes that only touch (lattice coordinates repeat exactly) must be reported.
  for (double r : {0.0, 0.01, 0.1, 0.3}) expect_matches_reference(s, r, "cube static");
}

TEST(FindCandidates, CubeBoundarySweptMatchesBruteForce) {
  TestSurface s = testing::cube_boundary(8, 1.0, {0.0, 0.0, 0.0});
  // A rigid shift: every swept box is the static box stretched along one direction.
  s.x1 = s.x0;
  for (std::size_t i = 0; i < s.x1.size(); i += 3) s.x1[i + 2] -= 0.2;
  for (double r : {0.0, 0.01, 0.1}) expect_matches_reference(s, r, "cube shifted");
  // An independent jiggle of every vertex.
  s.x1 = testing::randomly_moved(s.x0, 0.05, 7);
  for (double r : {0.0, 0.01, 0.1}) expect_matches_reference(s, r, "cube jiggled");
}

TEST(FindCandidates, PointOnBoxBoundaryIsReported) {
  // A vertex exactly on a face of a separate triangle's box, inflation 0: closed boxes.
  const TestSurface s{
      {1.0, 0.5, 0.5, 1.0, 0.0, 0.0, 2.0, 0.0, 0.0, 2.0, 1.0, 1.0}, {}, {1, 2, 2, 3, 1, 3}, {1, 2, 3}, {}};
  Candidates got;
  find_candidates(s.view(), 0.0, &got);
  ASSERT_EQ(got.vertex_face.size(), 1u);
  EXPECT_EQ(got.vertex_face[0], (std::array<std::int32_t, 2>{0, 0}));
  EXPECT_TRUE(got.edge_edge.empty());
}

TEST(FindCandidates, RepeatedCallsGiveIdenticalResults) {
  TestSurface s = testing::random_soup(11, 5, 200, 20);
  s.x1 = testing::randomly_moved(s.x0, 0.05, 12);
  Candidates first, second;
  find_candidates(s.view(), 0.01, &first);
  second.vertex_face.push_back({99, 99});  // stale content must be replaced
  find_candidates(s.view(), 0.01, &second);
  EXPECT_EQ(first.vertex_face, second.vertex_face);
  EXPECT_EQ(first.edge_edge, second.edge_edge);
}

}  // namespace
}  // namespace dipc::contact
