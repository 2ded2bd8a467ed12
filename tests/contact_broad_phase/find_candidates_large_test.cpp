// Prints find_candidates' wall time on cube boundaries from ~12K to ~200K triangles, static
// and swept, to show the O(n log n) scaling (a print, not an assertion: performance is
// measured, never asserted by timed tests). What it asserts is that every reported pair is
// sorted, unique, overlapping and free of shared vertices; completeness is checked against
// the brute force on smaller surfaces in find_candidates_test.cpp.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>

#include "brute_force_candidates.hpp"
#include "contact/broad_phase/find_candidates.hpp"

namespace dipc::contact {
namespace {

using testing::TestSurface;

void expect_valid(const TestSurface& s, double inflation, const Candidates& c) {
  for (std::size_t i = 0; i < c.vertex_face.size(); ++i) {
    const auto& p = c.vertex_face[i];
    if (i > 0) {
      ASSERT_LT(c.vertex_face[i - 1], p);
    }
    const std::int32_t* t = &s.faces[3 * p[1]];
    ASSERT_TRUE(t[0] != p[0] && t[1] != p[0] && t[2] != p[0]);
    ASSERT_TRUE(testing::reference_overlap(testing::reference_box(s, &p[0], 1, inflation),
                                           testing::reference_box(s, t, 3, inflation)));
  }
  for (std::size_t i = 0; i < c.edge_edge.size(); ++i) {
    const auto& p = c.edge_edge[i];
    if (i > 0) {
      ASSERT_LT(c.edge_edge[i - 1], p);
    }
    ASSERT_LT(p[0], p[1]);
    const std::int32_t* a = &s.edges[2 * p[0]];
    const std::int32_t* b = &s.edges[2 * p[1]];
    ASSERT_TRUE(a[0] != b[0] && a[0] != b[1] && a[1] != b[0] && a[1] != b[1]);
    ASSERT_TRUE(testing::reference_overlap(testing::reference_box(s, a, 2, inflation),
                                           testing::reference_box(s, b, 2, inflation)));
  }
}

double seconds_of(const TestSurface& s, double inflation, Candidates* out) {
  const auto start = std::chrono::steady_clock::now();
  find_candidates(s.view(), inflation, out);
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

TEST(BroadPhaseScaling, CubeBoundaryUpTo200KFaces) {
  std::printf("%9s %9s %9s | %10s %10s %10s | %10s %10s %10s\n", "faces", "edges", "vertices",
              "static s", "v-f", "e-e", "swept s", "v-f", "e-e");
  for (int n : {33, 65, 130}) {
    TestSurface s = testing::cube_boundary(n, 1.0, {0.0, 0.0, 0.0});
    const double h = 1.0 / n;
    const double inflation = 0.1 * h;
    Candidates still, swept;
    const double t_static = seconds_of(s, inflation, &still);
    expect_valid(s, inflation, still);
    s.x1 = testing::randomly_moved(s.x0, 0.6 * h, 3);
    const double t_swept = seconds_of(s, inflation, &swept);
    expect_valid(s, inflation, swept);
    EXPECT_FALSE(still.vertex_face.empty());
    EXPECT_FALSE(swept.edge_edge.empty());
    std::printf("%9zu %9zu %9d | %10.4f %10zu %10zu | %10.4f %10zu %10zu\n", s.faces.size() / 3,
                s.edges.size() / 2, s.num_vertices(), t_static, still.vertex_face.size(),
                still.edge_edge.size(), t_swept, swept.vertex_face.size(), swept.edge_edge.size());
  }
}

}  // namespace
}  // namespace dipc::contact
