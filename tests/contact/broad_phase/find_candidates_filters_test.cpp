// find_candidates' exclusions and filters: pairs sharing a vertex, the group filter (its
// arguments and their order), the per-pair keep callbacks, and empty inputs.
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <vector>

#include "brute_force_candidates.hpp"
#include "contact/broad_phase/find_candidates.hpp"

namespace dipc::contact {
namespace {

using Pairs = std::vector<std::array<std::int32_t, 2>>;
using testing::TestSurface;

// Two cubes 0.05 apart along x, group 0 and group 1.
TestSurface two_cubes() {
  TestSurface a = testing::cube_boundary(4, 1.0, {0.0, 0.0, 0.0}, 0);
  const TestSurface b = testing::cube_boundary(4, 1.0, {1.05, 0.2, 0.1}, 1);
  const auto offset = static_cast<std::int32_t>(a.num_vertices());
  a.x0.insert(a.x0.end(), b.x0.begin(), b.x0.end());
  for (std::int32_t id : b.faces) a.faces.push_back(id + offset);
  for (std::int32_t id : b.edges) a.edges.push_back(id + offset);
  a.groups.insert(a.groups.end(), b.groups.begin(), b.groups.end());
  return a;
}

TEST(FindCandidatesFilters, PairsSharingAVertexAreExcluded) {
  // Two triangles sharing the edge (1, 2); every box overlaps every other.
  TestSurface s;
  s.x0 = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0.1};
  s.faces = {0, 1, 2, 1, 3, 2};
  s.edges = testing::edges_of_faces(s.faces);  // (0,1) (0,2) (1,2) (1,3) (2,3)
  Candidates got;
  find_candidates(s.view(), 1.0, &got);
  EXPECT_EQ(got.vertex_face, (Pairs{{0, 1}, {3, 0}}));
  EXPECT_EQ(got.edge_edge, (Pairs{{0, 4}, {1, 3}}));
}

TEST(FindCandidatesFilters, DegenerateEdgeSharingBothVerticesIsExcluded) {
  TestSurface s;
  s.x0 = {0, 0, 0, 1, 0, 0};
  s.edges = {0, 1, 1, 0};
  Candidates got;
  find_candidates(s.view(), 0.1, &got);
  EXPECT_TRUE(got.edge_edge.empty());
}

TEST(FindCandidatesFilters, SelfContactOffKeepsOnlyPairsBetweenBodies) {
  const TestSurface s = two_cubes();
  const auto different = [](int a, int b) { return a != b; };
  Candidates got;
  find_candidates(s.view(), 0.04, &got, different);
  CandidateFilter filter;
  filter.allow_groups = different;
  const Candidates want = testing::brute_force_candidates(s, 0.04, filter);
  EXPECT_EQ(got.vertex_face, want.vertex_face);
  EXPECT_EQ(got.edge_edge, want.edge_edge);
  ASSERT_FALSE(got.vertex_face.empty());
  ASSERT_FALSE(got.edge_edge.empty());
  for (const auto& p : got.vertex_face) {
    EXPECT_NE(s.groups[p[0]], s.groups[s.faces[3 * p[1]]]);
  }
  for (const auto& p : got.edge_edge) {
    EXPECT_NE(s.groups[s.edges[2 * p[0]]], s.groups[s.edges[2 * p[1]]]);
  }
  // Without the filter the same-body pairs come back, so the filter did the removing.
  Candidates all;
  find_candidates(s.view(), 0.04, &all);
  EXPECT_GT(all.vertex_face.size(), got.vertex_face.size());
  EXPECT_GT(all.edge_edge.size(), got.edge_edge.size());
}

TEST(FindCandidatesFilters, GroupFilterGetsVertexGroupThenFaceGroup) {
  // Asymmetric on purpose: only body-0 vertices against body-1 faces survive.
  const TestSurface s = two_cubes();
  CandidateFilter filter;
  filter.allow_groups = [](int a, int b) { return a == 0 && b == 1; };
  Candidates got;
  find_candidates(s.view(), 0.04, &got, filter);
  const Candidates want = testing::brute_force_candidates(s, 0.04, filter);
  EXPECT_EQ(got.vertex_face, want.vertex_face);
  EXPECT_EQ(got.edge_edge, want.edge_edge);
  ASSERT_FALSE(got.vertex_face.empty());
  for (const auto& p : got.vertex_face) {
    EXPECT_EQ(s.groups[p[0]], 0);
    EXPECT_EQ(s.groups[s.faces[3 * p[1]]], 1);
  }
}

TEST(FindCandidatesFilters, KeepCallbacksSelectPairs) {
  TestSurface s = testing::random_soup(21, 5, 250, 30);
  s.x1 = testing::randomly_moved(s.x0, 0.05, 22);
  CandidateFilter filter;
  filter.keep_vertex_face = [](std::int32_t v, std::int32_t f) { return v % 3 == 0 || f % 2 == 0; };
  filter.keep_edge_edge = [](std::int32_t a, std::int32_t b) {
    EXPECT_LT(a, b);
    return (a + b) % 2 == 0;
  };
  Candidates got;
  find_candidates(s.view(), 0.02, &got, filter);
  const Candidates want = testing::brute_force_candidates(s, 0.02, filter);
  EXPECT_EQ(got.vertex_face, want.vertex_face);
  EXPECT_EQ(got.edge_edge, want.edge_edge);
  ASSERT_FALSE(got.vertex_face.empty());
  ASSERT_FALSE(got.edge_edge.empty());
  Candidates all;
  find_candidates(s.view(), 0.02, &all);
  EXPECT_GT(all.vertex_face.size(), got.vertex_face.size());
  EXPECT_GT(all.edge_edge.size(), got.edge_edge.size());
}

TEST(FindCandidatesFilters, EmptyInputsGiveNoPairs) {
  Candidates out;
  out.vertex_face.push_back({1, 2});
  out.edge_edge.push_back({3, 4});
  find_candidates(SurfaceView{}, 0.5, &out);
  EXPECT_TRUE(out.vertex_face.empty());
  EXPECT_TRUE(out.edge_edge.empty());

  // Vertices only, and vertices with one edge: nothing to pair with.
  const std::vector<double> x = {0, 0, 0, 0.1, 0, 0, 0.2, 0, 0};
  const std::vector<std::int32_t> edge = {0, 1};
  SurfaceView s;
  s.num_vertices = 3;
  s.x0 = x.data();
  find_candidates(s, 1.0, &out);
  EXPECT_TRUE(out.vertex_face.empty());
  EXPECT_TRUE(out.edge_edge.empty());
  s.num_edges = 1;
  s.edges = edge.data();
  find_candidates(s, 1.0, &out);
  EXPECT_TRUE(out.edge_edge.empty());
}

}  // namespace
}  // namespace dipc::contact
