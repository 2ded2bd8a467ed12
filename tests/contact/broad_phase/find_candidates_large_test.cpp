// find_candidates on cube boundaries from ~12K to ~200K triangles, static and swept: every
// reported pair is sorted, unique, overlapping and free of shared vertices. Completeness is
// checked against the brute force on smaller surfaces in find_candidates_test.cpp; the time
// and its O(n log n) scaling are measured by bench/broad_phase_bench.cpp (bench_broad_phase),
// not printed by a test.
#include <gtest/gtest.h>

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

TEST(FindCandidatesLarge, CubeBoundaryUpTo200KFacesGivesValidPairs) {
  for (int n : {33, 65, 130}) {
    TestSurface s = testing::cube_boundary(n, 1.0, {0.0, 0.0, 0.0});
    const double h = 1.0 / n;
    const double inflation = 0.1 * h;
    Candidates still, swept;
    find_candidates(s.view(), inflation, &still);
    expect_valid(s, inflation, still);
    s.x1 = testing::randomly_moved(s.x0, 0.6 * h, 3);
    find_candidates(s.view(), inflation, &swept);
    expect_valid(s, inflation, swept);
    EXPECT_FALSE(still.vertex_face.empty());
    EXPECT_FALSE(swept.edge_edge.empty());
  }
}

}  // namespace
}  // namespace dipc::contact
