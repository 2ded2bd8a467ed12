// The broad phase's pair filters (pair_filter.hpp), the one formula that the CPU search (through
// CandidateFilter) and the device search apply: group rules with and without self-contact and
// for obstacles (group −1), a vertex–face pair kept by its vertex's owner or, for kFaceDecides
// vertices, by the face's owner, an edge–edge pair kept by the owner of the edge with the
// smaller global id, and no filtering where the arrays are absent. Then find_candidates with
// those filters on two touching triangles keeps exactly the pairs the rules name.
#include "contact/broad_phase/pair_filter.hpp"

#include <gtest/gtest.h>

#include <vector>

#include "contact/broad_phase/find_candidates.hpp"

namespace dipc::contact {
namespace {

TEST(PairFilter, GroupsMayTouch) {
  const char self[2] = {0, 1};  // group 0 without self-contact, group 1 with
  PairFilter f;
  f.self = self;
  f.num_self = 2;
  EXPECT_TRUE(groups_may_touch(f, 0, 1));
  EXPECT_TRUE(groups_may_touch(f, 1, 0));
  EXPECT_FALSE(groups_may_touch(f, 0, 0));
  EXPECT_TRUE(groups_may_touch(f, 1, 1));
  EXPECT_FALSE(groups_may_touch(f, 2, 2));  // beyond the list: no self-contact
  EXPECT_TRUE(groups_may_touch(f, -1, 0));  // obstacle and body
  EXPECT_TRUE(groups_may_touch(f, 1, -1));
  EXPECT_FALSE(groups_may_touch(f, -1, -1));  // obstacle and obstacle
}

TEST(PairFilter, OwnershipRules) {
  PairFilter f;
  EXPECT_TRUE(keeps_vertex_face(f, 0, 0));  // no arrays: every pair kept
  EXPECT_TRUE(keeps_edge_edge(f, 0, 1));
  const char owned_vertex[3] = {1, 0, kFaceDecides};
  const char owned_face[2] = {0, 1};
  const std::int64_t edge_gid[3] = {40, 10, 20};
  const char owned_edge[3] = {1, 0, 1};
  f.owned_vertex = owned_vertex;
  f.owned_face = owned_face;
  f.edge_gid = edge_gid;
  f.owned_edge = owned_edge;
  EXPECT_TRUE(keeps_vertex_face(f, 0, 0));   // owned vertex, whatever the face
  EXPECT_FALSE(keeps_vertex_face(f, 1, 1));  // vertex owned elsewhere
  EXPECT_FALSE(keeps_vertex_face(f, 2, 0));  // the face decides: not owned
  EXPECT_TRUE(keeps_vertex_face(f, 2, 1));   // the face decides: owned
  EXPECT_FALSE(keeps_edge_edge(f, 0, 1));    // gid 10 < 40: edge 1 decides, owned elsewhere
  EXPECT_TRUE(keeps_edge_edge(f, 0, 2));     // gid 20 < 40: edge 2 decides, owned here
  EXPECT_TRUE(keeps_edge_edge(f, 2, 0));
  EXPECT_FALSE(keeps_edge_edge(f, 1, 2));  // gid 10 < 20: edge 1 decides
}

// Two triangles of different groups, 0.1 apart, so every vertex meets the other triangle.
// Vertices 0..2 (triangle 0, group 0) are owned here, vertices 3..5 (triangle 1, group 1)
// leave their pairs to the face's owner, and only triangle 0 is owned; edges are owned by the
// side with the smaller global id, which is triangle 1's.
TEST(PairFilter, FiltersTheSearch) {
  const std::vector<double> x{0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 0.1, 1, 0, 0.1, 0, 1, 0.1};
  const std::vector<std::int32_t> faces{0, 1, 2, 3, 4, 5};
  const std::vector<std::int32_t> edges{0, 1, 1, 2, 2, 0, 3, 4, 4, 5, 5, 3};
  const std::vector<std::int32_t> group{0, 0, 0, 1, 1, 1};
  SurfaceView view;
  view.num_vertices = 6;
  view.x0 = x.data();
  view.num_edges = 6;
  view.edges = edges.data();
  view.num_faces = 2;
  view.faces = faces.data();
  view.vertex_group = group.data();
  const char owned_vertex[6] = {1, 1, 1, kFaceDecides, kFaceDecides, kFaceDecides};
  const char owned_face[2] = {1, 0};
  const std::int64_t edge_gid[6] = {10, 11, 12, 0, 1, 2};
  const char owned_edge[6] = {1, 1, 1, 0, 1, 0};
  PairFilter pf;
  pf.group = group.data();
  pf.owned_vertex = owned_vertex;
  pf.owned_face = owned_face;
  pf.edge_gid = edge_gid;
  pf.owned_edge = owned_edge;
  CandidateFilter filter;
  filter.allow_groups = [&](int a, int b) { return groups_may_touch(pf, a, b); };
  filter.keep_vertex_face = [&](std::int32_t v, std::int32_t f) { return keeps_vertex_face(pf, v, f); };
  filter.keep_edge_edge = [&](std::int32_t a, std::int32_t b) { return keeps_edge_edge(pf, a, b); };
  Candidates c;
  find_candidates(view, 0.2, &c, filter);
  // Owned vertices 0..2 against triangle 1; vertices 3..5 against triangle 0 (owned face).
  const std::vector<std::array<std::int32_t, 2>> vf{{0, 1}, {1, 1}, {2, 1}, {3, 0}, {4, 0}, {5, 0}};
  EXPECT_EQ(c.vertex_face, vf);
  // Edge pairs across the groups whose deciding (triangle 1) edge is owned: edge 4 only.
  const std::vector<std::array<std::int32_t, 2>> ee{{0, 4}, {1, 4}, {2, 4}};
  EXPECT_EQ(c.edge_edge, ee);
}

}  // namespace
}  // namespace dipc::contact
