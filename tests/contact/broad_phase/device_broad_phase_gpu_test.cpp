// The device broad phase (contact/broad_phase/cuda/device_broad_phase.hpp) against
// contact::find_candidates with the same inputs and the equivalent CandidateFilter: the same
// vertex–face and edge–edge lists, pair for pair and in the same order, on random soups, deformed
// cube boundaries with swept and static boxes, self-contact on and off, ownership filters,
// boxes that only touch, coincident vertices, empty and one-primitive inputs and surfaces of
// about 100K triangles; the same errors with the same messages; and the segment search as
// ContactForm forms its boxes, also with triangle-mesh obstacles (vertices on prescribed
// segments, pairs owned by the body face's owner).
// Skips where no GPU is present; runs on the lent GPU machine.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "contact/broad_phase/cuda/device_broad_phase.hpp"
#include "contact/broad_phase/find_candidates.hpp"
#include "device/device_runtime.hpp"
#include "test_surfaces.hpp"

namespace dipc::contact {
namespace {

using Pairs = std::vector<std::array<std::int32_t, 2>>;
using testing::TestSurface;

// The filters of a case as data (device::BroadPhaseSurface's fields); empty: no such filter.
struct Filters {
  bool groups = false;  // use TestSurface::groups with self_contact
  std::vector<char> self_contact;
  std::vector<char> owned_vertex;
  std::vector<std::int64_t> edge_gid;
  std::vector<char> owned_edge;
};

device::BroadPhaseSurface device_surface(const TestSurface& s, const Filters& f) {
  device::BroadPhaseSurface d;
  d.num_vertices = s.num_vertices();
  d.edges = s.edges;
  d.faces = s.faces;
  if (f.groups) d.vertex_group = s.groups;
  d.self_contact = f.self_contact;
  d.owned_vertex = f.owned_vertex;
  d.edge_gid = f.edge_gid;
  d.owned_edge = f.owned_edge;
  return d;
}

// The CandidateFilter that device_broad_phase.hpp says the data stands for (ContactForm's).
CandidateFilter host_filter(const Filters& f) {
  CandidateFilter filter;
  if (f.groups) {
    filter.allow_groups = [self = f.self_contact](int a, int b) {
      return a != b || (a >= 0 && a < static_cast<int>(self.size()) && self[a]);
    };
  }
  if (!f.owned_vertex.empty())
    filter.keep_vertex_face = [&f](std::int32_t v, std::int32_t) { return f.owned_vertex[v] != 0; };
  if (!f.edge_gid.empty()) {
    filter.keep_edge_edge = [&f](std::int32_t a, std::int32_t b) {
      return f.owned_edge[f.edge_gid[a] < f.edge_gid[b] ? a : b] != 0;
    };
  }
  return filter;
}

// Equal lists, reported by their sizes and first difference (the lists can hold millions).
::testing::AssertionResult same_pairs(const Pairs& got, const Pairs& want) {
  const auto diff = std::mismatch(got.begin(), got.end(), want.begin(), want.end());
  if (diff.first == got.end() && diff.second == want.end()) return ::testing::AssertionSuccess();
  const auto at = static_cast<std::size_t>(diff.first - got.begin());
  auto show = [](const Pairs& p, std::size_t i) {
    return i < p.size() ? "(" + std::to_string(p[i][0]) + ", " + std::to_string(p[i][1]) + ")" : std::string("end");
  };
  return ::testing::AssertionFailure() << "device " << got.size() << " pairs, host " << want.size()
                                       << "; first difference at " << at << ": device " << show(got, at) << ", host "
                                       << show(want, at);
}

struct Counts {
  std::size_t vertex_face = 0, edge_edge = 0;
};

// Runs both searches on s (swept when s.x1 is set) and expects the same lists; returns their
// sizes so callers can check a case is not vacuous. `search` is reused across cases, so its
// workspace is exercised growing and shrinking.
Counts expect_same(device::DeviceBroadPhase& search, const TestSurface& s, double inflation, const Filters& f,
                   const std::string& label) {
  SCOPED_TRACE(label + ", inflation " + std::to_string(inflation));
  search.upload(device_surface(s, f));
  device::Array<double> x0("test x0"), x1("test x1");
  x0.upload(s.x0);
  x1.upload(s.x1);
  Candidates got, want;
  got.vertex_face = {{-1, -1}};  // replaced, as on the host
  search.find_candidates(x0.data(), s.x1.empty() ? nullptr : x1.data(), inflation, &got);
  find_candidates(s.view(), inflation, &want, host_filter(f));
  EXPECT_TRUE(same_pairs(got.vertex_face, want.vertex_face)) << "vertex-face";
  EXPECT_TRUE(same_pairs(got.edge_edge, want.edge_edge)) << "edge-edge";
  return {want.vertex_face.size(), want.edge_edge.size()};
}

// Appends b to a as a second body (group 1).
TestSurface join(TestSurface a, const TestSurface& b) {
  const auto offset = static_cast<std::int32_t>(a.num_vertices());
  a.x0.insert(a.x0.end(), b.x0.begin(), b.x0.end());
  if (!a.x1.empty() || !b.x1.empty()) {
    if (a.x1.empty()) a.x1 = std::vector<double>(a.x0.begin(), a.x0.begin() + 3 * offset);
    a.x1.insert(a.x1.end(), b.x1.empty() ? b.x0.begin() : b.x1.begin(), b.x1.empty() ? b.x0.end() : b.x1.end());
  }
  for (std::int32_t id : b.faces) a.faces.push_back(id + offset);
  for (std::int32_t id : b.edges) a.edges.push_back(id + offset);
  std::vector<std::int32_t> groups = b.groups;
  if (groups.empty()) groups.assign(b.num_vertices(), 1);
  if (a.groups.empty()) a.groups.assign(offset, 0);
  a.groups.insert(a.groups.end(), groups.begin(), groups.end());
  return a;
}

// A cube boundary bent by a smooth deformation (no two coordinates repeat as on the lattice).
TestSurface deformed_cube(int n, const std::array<double, 3>& origin, std::int32_t group) {
  TestSurface s = testing::cube_boundary(n, 1.0, origin, group);
  for (std::size_t v = 0; 3 * v < s.x0.size(); ++v) {
    double* p = &s.x0[3 * v];
    const double x = p[0], y = p[1], z = p[2];
    p[0] += 0.05 * std::sin(3.1 * y + 0.3) * std::cos(1.7 * z);
    p[1] += 0.04 * std::sin(2.3 * z + 1.1) + 0.02 * x * x;
    p[2] += 0.03 * std::cos(2.9 * x - 0.4) * y;
  }
  return s;
}

// x0 moved by a smooth motion plus noise of amplitude `noise`.
std::vector<double> swept_end(const std::vector<double>& x0, const std::array<double, 3>& shift, double noise,
                              unsigned seed) {
  std::vector<double> x1 = testing::randomly_moved(x0, noise, seed);
  for (std::size_t k = 0; k < x1.size(); ++k) x1[k] += shift[k % 3] * (1.0 + 0.3 * std::sin(7.0 * x0[k]));
  return x1;
}

// Random ownership of vertices, and random global ids (a permutation) and ownership of edges.
Filters random_ownership(const TestSurface& s, unsigned seed, double owned_fraction) {
  std::mt19937 rng(seed);
  std::bernoulli_distribution owned(owned_fraction);
  Filters f;
  for (int v = 0; v < s.num_vertices(); ++v) f.owned_vertex.push_back(owned(rng) ? 1 : 0);
  const std::size_t ne = s.edges.size() / 2;
  for (std::size_t e = 0; e < ne; ++e) f.edge_gid.push_back(static_cast<std::int64_t>(1000 + 3 * e));
  std::shuffle(f.edge_gid.begin(), f.edge_gid.end(), rng);
  for (std::size_t e = 0; e < ne; ++e) f.owned_edge.push_back(owned(rng) ? 1 : 0);
  return f;
}

TEST(DeviceBroadPhase, RandomSoupsStaticAndSwept) {
  if (device::device_count() == 0) GTEST_SKIP() << "no CUDA device";
  device::DeviceBroadPhase search;
  for (unsigned seed : {1u, 2u, 3u, 4u}) {
    TestSurface s = testing::random_soup(seed, 8, 2000, 100);
    for (double r : {0.0, 1e-3, 0.02, 0.08}) {
      const Counts c = expect_same(search, s, r, {}, "soup " + std::to_string(seed) + " static");
      EXPECT_GT(c.vertex_face, 0u);
      EXPECT_GT(c.edge_edge, 0u);
    }
    s.x1 = testing::randomly_moved(s.x0, 0.1, seed + 100);
    for (double r : {0.0, 1e-3, 0.02}) expect_same(search, s, r, {}, "soup " + std::to_string(seed) + " swept");
  }
}

TEST(DeviceBroadPhase, DeformedCubesSweptAndStatic) {
  if (device::device_count() == 0) GTEST_SKIP() << "no CUDA device";
  device::DeviceBroadPhase search;
  // Two bent cubes 0.02 apart, the second moving into the first.
  TestSurface a = deformed_cube(12, {0.0, 0.0, 0.0}, 0);
  TestSurface b = deformed_cube(10, {1.02, 0.1, -0.2}, 1);
  TestSurface s = join(a, b);
  for (double r : {0.0, 0.005, 0.02}) expect_same(search, s, r, {}, "deformed cubes static");
  s.x1 = swept_end(s.x0, {-0.03, 0.01, 0.005}, 0.01, 9);
  for (double r : {0.0, 0.005, 0.02}) {
    const Counts c = expect_same(search, s, r, {}, "deformed cubes swept");
    EXPECT_GT(c.vertex_face, 0u);
    EXPECT_GT(c.edge_edge, 0u);
  }
}

TEST(DeviceBroadPhase, SelfContactOnAndOff) {
  if (device::device_count() == 0) GTEST_SKIP() << "no CUDA device";
  device::DeviceBroadPhase search;
  // 0.015 apart (the bending moves both x-faces alike), closer than 2 · 0.01: pairs between
  // the bodies even with self-contact off.
  TestSurface s = join(deformed_cube(10, {0.0, 0.0, 0.0}, 0), deformed_cube(8, {1.015, 0.2, 0.1}, 1));
  s.x1 = swept_end(s.x0, {0.0, 0.0, 0.02}, 0.02, 5);
  // A few vertices in group 5 (beyond every flag list) and −1 (never a valid index).
  for (std::size_t v = 0; v < s.groups.size(); v += 37) s.groups[v] = v % 2 ? 5 : -1;
  Filters off;
  off.groups = true;
  const Counts none = expect_same(search, s, 0.01, off, "self contact off (no flags)");
  for (const std::vector<char>& self : {std::vector<char>{0, 0}, std::vector<char>{1, 0}, std::vector<char>{0, 1},
                                        std::vector<char>{1, 1, 0, 0, 0, 1}}) {
    Filters f;
    f.groups = true;
    f.self_contact = self;
    const Counts c = expect_same(search, s, 0.01, f, "self contact flags of size " + std::to_string(self.size()));
    EXPECT_GE(c.vertex_face, none.vertex_face);
  }
  Filters all;
  all.groups = true;
  all.self_contact = {1, 1};
  const Counts on = expect_same(search, s, 0.01, all, "self contact on");
  EXPECT_GT(on.vertex_face, none.vertex_face);
  EXPECT_GT(none.vertex_face, 0u) << "the bodies must be close enough to give pairs between them";
}

TEST(DeviceBroadPhase, OwnershipFilters) {
  if (device::device_count() == 0) GTEST_SKIP() << "no CUDA device";
  device::DeviceBroadPhase search;
  TestSurface s = join(deformed_cube(10, {0.0, 0.0, 0.0}, 0), deformed_cube(9, {1.02, 0.1, 0.0}, 1));
  s.x1 = swept_end(s.x0, {-0.02, 0.0, 0.0}, 0.01, 11);
  for (double fraction : {0.0, 0.3, 0.7, 1.0}) {
    Filters f = random_ownership(s, 17, fraction);
    expect_same(search, s, 0.01, f, "ownership " + std::to_string(fraction));
    f.groups = true;
    f.self_contact = {1, 0};
    expect_same(search, s, 0.01, f, "ownership and groups " + std::to_string(fraction));
  }
  // Only one of the two filters at a time.
  Filters vertices_only = random_ownership(s, 23, 0.5);
  vertices_only.edge_gid.clear();
  vertices_only.owned_edge.clear();
  expect_same(search, s, 0.01, vertices_only, "vertex ownership only");
  Filters edges_only = random_ownership(s, 29, 0.5);
  edges_only.owned_vertex.clear();
  expect_same(search, s, 0.01, edges_only, "edge ownership only");
}

TEST(DeviceBroadPhase, TouchingBoxes) {
  if (device::device_count() == 0) GTEST_SKIP() << "no CUDA device";
  device::DeviceBroadPhase search;
  // Lattice coordinates i/8 are exact: with inflation 0 neighbouring boxes touch, with 1/16 the
  // boxes of primitives one cell apart touch, and the second cube lies exactly 2 · (1/16) away.
  const TestSurface cube = testing::cube_boundary(8, 1.0, {0.0, 0.0, 0.0});
  for (double r : {0.0, 0.0625, 0.125}) expect_same(search, cube, r, {}, "lattice cube");
  TestSurface two = join(cube, testing::cube_boundary(4, 1.0, {1.125, 0.25, 0.0}, 1));
  Filters between;
  between.groups = true;
  const Counts touching = expect_same(search, two, 0.0625, between, "cubes exactly 2r apart");
  EXPECT_GT(touching.vertex_face, 0u) << "touching boxes overlap";
  const Counts apart = expect_same(search, two, 0.0625 - 1e-12, between, "cubes just beyond 2r");
  EXPECT_EQ(apart.vertex_face, 0u);
  // A rigid shift that ends exactly on the lattice: swept boxes touch too.
  TestSurface shifted = two;
  shifted.x1 = shifted.x0;
  for (std::size_t v = 3 * cube.num_vertices(); v < shifted.x1.size(); v += 3) shifted.x1[v] -= 0.125;
  expect_same(search, shifted, 0.0, between, "shift onto contact");
}

TEST(DeviceBroadPhase, CoincidentAndDegenerateGeometry) {
  if (device::device_count() == 0) GTEST_SKIP() << "no CUDA device";
  device::DeviceBroadPhase search;
  // Every vertex at one point: all Morton codes equal (the tree splits by index only) and every
  // box overlaps every other.
  TestSurface point = testing::random_soup(3, 4, 200, 20);
  std::fill(point.x0.begin(), point.x0.end(), 0.25);
  expect_same(search, point, 0.0, {}, "one point");
  // Huge triangles across small ones, and a flat layer (zero extent along z).
  TestSurface mixed = testing::random_soup(7, 10, 3000, 0);
  const std::int32_t base = mixed.num_vertices();
  mixed.x0.insert(mixed.x0.end(), {-5, -5, 0.5, 5, -5, 0.5, 0, 5, 0.5, -5, 5, 0.4, 5, 5, 0.6, 0, -5, 0.5});
  mixed.faces.insert(mixed.faces.end(), {base, base + 1, base + 2, base + 3, base + 4, base + 5});
  mixed.edges = testing::edges_of_faces(mixed.faces);
  for (double r : {0.0, 0.01}) expect_same(search, mixed, r, {}, "huge triangles");
  TestSurface flat = testing::random_soup(8, 10, 2000, 50);
  for (std::size_t k = 2; k < flat.x0.size(); k += 3) flat.x0[k] = 0.0;
  for (double r : {0.0, 0.01}) expect_same(search, flat, r, {}, "flat");
}

TEST(DeviceBroadPhase, EmptyAndTinyInputs) {
  if (device::device_count() == 0) GTEST_SKIP() << "no CUDA device";
  device::DeviceBroadPhase search;
  Filters groups;
  groups.groups = true;
  const TestSurface empty;
  Counts c = expect_same(search, empty, 0.1, {}, "nothing");
  EXPECT_EQ(c.vertex_face + c.edge_edge, 0u);
  TestSurface points;  // vertices only
  points.x0 = {0, 0, 0, 0.1, 0, 0, 0, 0.1, 0};
  points.groups = {0, 0, 1};
  c = expect_same(search, points, 0.1, groups, "vertices only");
  EXPECT_EQ(c.vertex_face + c.edge_edge, 0u);
  TestSurface one;  // one triangle and a vertex above it: a tree of one leaf
  one.x0 = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0.2, 0.2, 0.05};
  one.faces = {0, 1, 2};
  one.edges = testing::edges_of_faces(one.faces);
  c = expect_same(search, one, 0.1, {}, "one triangle");
  EXPECT_EQ(c.vertex_face, 1u);
  TestSurface edges;  // two crossing edges, no triangles
  edges.x0 = {0, 0, 0, 1, 1, 0, 1, 0, 0.01, 0, 1, 0.01};
  edges.edges = {0, 1, 2, 3};
  c = expect_same(search, edges, 0.01, {}, "two edges");
  EXPECT_EQ(c.edge_edge, 1u);
  edges.edges = {0, 1};
  c = expect_same(search, edges, 0.01, {}, "one edge");
  EXPECT_EQ(c.edge_edge, 0u);
  // A larger surface after the small ones, then an empty one again: the workspace is reused.
  expect_same(search, testing::random_soup(5, 6, 500, 20), 0.02, {}, "soup after tiny inputs");
  expect_same(search, empty, 0.0, {}, "nothing again");
}

TEST(DeviceBroadPhase, HundredThousandTriangles) {
  if (device::device_count() == 0) GTEST_SKIP() << "no CUDA device";
  device::DeviceBroadPhase search;
  // 6 · 2 · 91² = 99,372 triangles.
  const int n = 91;
  const double h = 1.0 / n;
  TestSurface cube = testing::cube_boundary(n, 1.0, {0.0, 0.0, 0.0});
  Counts c = expect_same(search, cube, 0.1 * h, {}, "lattice cube, static");
  EXPECT_GT(c.vertex_face, 0u);
  cube.x1 = testing::randomly_moved(cube.x0, 0.6 * h, 3);
  c = expect_same(search, cube, 0.1 * h, random_ownership(cube, 4, 0.5), "lattice cube, swept, owned");
  EXPECT_GT(c.edge_edge, 0u);
  TestSurface bent = deformed_cube(n, {0.0, 0.0, 0.0}, 0);
  bent.x1 = swept_end(bent.x0, {0.5 * h, -0.2 * h, 0.1 * h}, 0.3 * h, 8);
  expect_same(search, bent, 0.25 * h, {}, "deformed cube, swept");
  TestSurface soup = testing::random_soup(11, 40, 100000, 2000);
  expect_same(search, soup, 0.002, {}, "soup, static");
  soup.x1 = testing::randomly_moved(soup.x0, 0.005, 12);
  Filters f = random_ownership(soup, 13, 0.6);
  soup.groups.assign(soup.num_vertices(), 0);
  for (std::size_t v = 0; v < soup.groups.size(); ++v) soup.groups[v] = static_cast<std::int32_t>(v % 3);
  f.groups = true;
  f.self_contact = {1, 0, 1};
  expect_same(search, soup, 0.002, f, "soup, swept, groups and ownership");
}

// The thrown message, "" when nothing is thrown.
template <class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const BroadPhaseError& e) {
    return e.what();
  }
  return "";
}

TEST(DeviceBroadPhase, SameErrorsAsTheHost) {
  if (device::device_count() == 0) GTEST_SKIP() << "no CUDA device";
  TestSurface s;
  s.x0 = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0};
  s.faces = {0, 1, 2, 1, 3, 2};
  s.edges = testing::edges_of_faces(s.faces);
  device::DeviceBroadPhase search;
  search.upload(device_surface(s, {}));
  device::Array<double> x0("test x0"), x1("test x1");
  x0.upload(s.x0);
  Candidates out;
  auto both = [&](const TestSurface& t, const double* d0, const double* d1, double r, Candidates* o) {
    const std::string host = error_of([&] { find_candidates(t.view(), r, o); });
    const std::string dev = error_of([&] { search.find_candidates(d0, d1, r, o); });
    EXPECT_FALSE(host.empty());
    EXPECT_EQ(dev, host);
  };
  both(s, x0.data(), nullptr, -1.0, &out);
  both(s, x0.data(), nullptr, std::numeric_limits<double>::quiet_NaN(), &out);
  both(s, x0.data(), nullptr, std::numeric_limits<double>::infinity(), &out);
  both(s, x0.data(), nullptr, 0.1, nullptr);
  SurfaceView view = s.view();
  view.x0 = nullptr;
  EXPECT_EQ(error_of([&] { search.find_candidates(nullptr, nullptr, 0.1, &out); }),
            error_of([&] { find_candidates(view, 0.1, &out); }));
  // Non-finite coordinates: the same vertex and coordinate, x0 before x1.
  TestSurface bad = s;
  bad.x0[3 * 2 + 1] = std::numeric_limits<double>::infinity();
  bad.x0[3 * 3 + 0] = std::numeric_limits<double>::quiet_NaN();
  bad.x1 = s.x0;
  bad.x1[3 * 1 + 2] = std::numeric_limits<double>::quiet_NaN();
  x0.upload(bad.x0);
  x1.upload(bad.x1);
  both(bad, x0.data(), x1.data(), 0.1, &out);
  bad.x0 = s.x0;
  x0.upload(bad.x0);
  both(bad, x0.data(), x1.data(), 0.1, &out);
  // Ids out of range are caught at upload, with the host's message.
  TestSurface out_of_range = s;
  out_of_range.faces[4] = 7;
  EXPECT_EQ(error_of([&] { search.upload(device_surface(out_of_range, {})); }),
            error_of([&] { find_candidates(out_of_range.view(), 0.1, &out); }));
  out_of_range = s;
  out_of_range.edges[3] = -1;
  EXPECT_EQ(error_of([&] { search.upload(device_surface(out_of_range, {})); }),
            error_of([&] { find_candidates(out_of_range.view(), 0.1, &out); }));
  // Filter arrays of the wrong length.
  device::BroadPhaseSurface short_groups = device_surface(s, {});
  short_groups.vertex_group = {0, 1};
  EXPECT_NE(error_of([&] { search.upload(short_groups); }), "");
}

TEST(DeviceBroadPhase, SegmentSearchFormsBoxesAsContactForm) {
  if (device::device_count() == 0) GTEST_SKIP() << "no CUDA device";
  // Surface vertices are rows of larger node arrays (as ContactForm's compact numbering maps
  // them to ext-local nodes): x0 = x[node], x1 = x0 + p[node], static when p is zero there.
  // Two lattice cubes 0.015 apart, closer than 2 · 0.01: pairs between them at p = 0.
  TestSurface s = join(testing::cube_boundary(8, 1.0, {0.0, 0.0, 0.0}),
                       testing::cube_boundary(6, 1.0, {1.015, 0.1, 0.1}, 1));
  const int nv = s.num_vertices(), num_nodes = 2 * nv + 5;
  std::vector<std::int32_t> node(num_nodes);
  for (int n = 0; n < num_nodes; ++n) node[n] = n;
  std::mt19937 rng(2);
  std::shuffle(node.begin(), node.end(), rng);
  node.resize(nv);
  std::vector<double> x(3 * num_nodes, 1e300), p(3 * num_nodes, 0.0);  // unused rows stay far away
  for (int v = 0; v < nv; ++v)
    for (int c = 0; c < 3; ++c) x[3 * node[v] + c] = s.x0[3 * v + c];
  Filters f = random_ownership(s, 31, 0.5);
  f.groups = true;
  device::BroadPhaseSurface d = device_surface(s, f);
  d.vertex_node = node;
  device::DeviceBroadPhase search;
  search.upload(d);
  device::Array<double> x_device("test x"), p_device("test p");
  x_device.upload(x);
  auto expect_segment = [&](const std::string& label) {
    SCOPED_TRACE(label);
    p_device.upload(p);
    Candidates got, want;
    search.find_candidates_on_segment(x_device.data(), p_device.data(), 0.01, &got);
    TestSurface host = s;
    host.x1.assign(3 * nv, 0.0);
    bool moving = false;
    for (int v = 0; v < nv; ++v)
      for (int c = 0; c < 3; ++c) {
        host.x1[3 * v + c] = host.x0[3 * v + c] + p[3 * node[v] + c];
        moving = moving || p[3 * node[v] + c] != 0.0;
      }
    if (!moving) host.x1.clear();
    find_candidates(host.view(), 0.01, &want, host_filter(f));
    EXPECT_TRUE(same_pairs(got.vertex_face, want.vertex_face));
    EXPECT_TRUE(same_pairs(got.edge_edge, want.edge_edge));
    EXPECT_GT(want.vertex_face.size(), 0u);
  };
  expect_segment("p = 0");
  for (int k = 0; k < 3 * num_nodes; k += 3) p[k] = -0.0;  // still no motion
  expect_segment("p = -0");
  std::uniform_real_distribution<double> u(-0.02, 0.02);
  for (int v = 0; v < nv; ++v)
    for (int c = 0; c < 3; ++c) p[3 * node[v] + c] = u(rng) - (c == 0 && s.groups[v] == 1 ? 0.03 : 0.0);
  expect_segment("moving");
}

TEST(DeviceBroadPhase, PrescribedVerticesAndFaceOwnedPairsAsContactForm) {
  if (device::device_count() == 0) GTEST_SKIP() << "no CUDA device";
  // A body (a deformed cube, group 0, its vertices rows of x and p) and an obstacle after it
  // (a lattice cube in group −1, which never meets itself, its vertices rows of prescribed
  // start and end positions): ContactForm's triangle-mesh obstacles. The obstacle's vertex–face
  // pairs belong to the owner of the body face (kFaceDecides, owned_face), its edges have the
  // largest global id (the body edge's owner decides).
  const TestSurface body = deformed_cube(7, {0.0, 0.0, 0.0}, 0);
  TestSurface obstacle = testing::cube_boundary(5, 1.0, {1.02, 0.15, 0.1});
  const TestSurface s = join(body, obstacle);
  const int nb = body.num_vertices(), no = obstacle.num_vertices(), nv = nb + no;
  const int body_edges = static_cast<int>(body.edges.size() / 2), body_faces = static_cast<int>(body.faces.size() / 3);
  Filters f = random_ownership(s, 41, 0.5);
  f.groups = true;
  f.self_contact = {1};  // the body touches itself; the obstacle (−1) never does
  std::vector<std::int32_t> groups = s.groups;
  for (int v = nb; v < nv; ++v) groups[v] = -1, f.owned_vertex[v] = device::kFaceDecides;
  for (std::size_t e = body_edges; e < s.edges.size() / 2; ++e)
    f.edge_gid[e] = std::numeric_limits<std::int64_t>::max(), f.owned_edge[e] = 0;
  std::vector<char> owned_face(s.faces.size() / 3, 0);
  std::mt19937 rng(43);
  for (int k = 0; k < body_faces; ++k) owned_face[k] = rng() % 2;
  device::BroadPhaseSurface d = device_surface(s, f);
  d.vertex_group = groups;
  d.owned_face = owned_face;
  // Body vertices are shuffled rows of larger node arrays; obstacle vertex k is row −2 − k.
  const int num_nodes = 2 * nb + 3;
  std::vector<std::int32_t> node(num_nodes);
  for (int n = 0; n < num_nodes; ++n) node[n] = n;
  std::shuffle(node.begin(), node.end(), rng);
  node.resize(nb);
  for (int k = 0; k < no; ++k) node.push_back(-2 - k);
  d.vertex_node = node;
  device::DeviceBroadPhase search;
  search.upload(d);

  // ContactForm's host filter with the same data.
  CandidateFilter filter;
  filter.allow_groups = [](int a, int b) {
    if (a < 0 || b < 0) return a >= 0 || b >= 0;
    return a != b || a == 0;
  };
  filter.keep_vertex_face = [&](std::int32_t v, std::int32_t face) {
    return f.owned_vertex[v] == device::kFaceDecides ? owned_face[face] != 0 : f.owned_vertex[v] != 0;
  };
  filter.keep_edge_edge = [&](std::int32_t a, std::int32_t b) {
    return f.owned_edge[f.edge_gid[a] < f.edge_gid[b] ? a : b] != 0;
  };

  std::vector<double> x(3 * num_nodes, 1e300), p(3 * num_nodes, 0.0);  // unused rows stay far away
  for (int v = 0; v < nb; ++v)
    for (int c = 0; c < 3; ++c) x[3 * node[v] + c] = s.x0[3 * v + c];
  std::vector<double> start(s.x0.begin() + 3 * nb, s.x0.end()), end = start;
  device::Array<double> x_device("test x"), p_device("test p"), start_device("test start"), end_device("test end");
  x_device.upload(x);
  auto expect_segment = [&](const std::string& label, bool obstacle_moving) {
    SCOPED_TRACE(label);
    p_device.upload(p);
    start_device.upload(start);
    end_device.upload(end);
    Candidates got, want;
    search.find_candidates_on_segment(x_device.data(), p_device.data(), 0.01, &got,
                                      {start_device.data(), end_device.data(), obstacle_moving});
    TestSurface host = s;
    host.groups = groups;
    host.x1.assign(3 * nv, 0.0);
    bool moving = obstacle_moving;
    for (int v = 0; v < nb; ++v)
      for (int c = 0; c < 3; ++c) {
        host.x1[3 * v + c] = host.x0[3 * v + c] + p[3 * node[v] + c];
        moving = moving || p[3 * node[v] + c] != 0.0;
      }
    std::copy(start.begin(), start.end(), host.x0.begin() + 3 * nb);
    std::copy(end.begin(), end.end(), host.x1.begin() + 3 * nb);
    if (!moving) host.x1.clear();
    find_candidates(host.view(), 0.01, &want, filter);
    EXPECT_TRUE(same_pairs(got.vertex_face, want.vertex_face));
    EXPECT_TRUE(same_pairs(got.edge_edge, want.edge_edge));
    // Not vacuous: pairs of the obstacle's vertices, of its faces and of its edges.
    auto count = [](const Pairs& pairs, auto&& test) {
      return std::count_if(pairs.begin(), pairs.end(), [&](const auto& q) { return test(q[0], q[1]); });
    };
    EXPECT_GT(count(want.vertex_face, [&](int v, int) { return v >= nb; }), 0);
    EXPECT_GT(count(want.vertex_face, [&](int v, int face) { return v < nb && face >= body_faces; }), 0);
    EXPECT_GT(count(want.edge_edge, [&](int, int b) { return b >= body_edges; }), 0);
    return want.vertex_face.size() + want.edge_edge.size();
  };
  // 0.02 apart: pairs between body and obstacle at rest (inflation 0.01 on each side).
  const std::size_t at_rest = expect_segment("all still", false);
  // The obstacle alone moves 0.05 towards the body (a prescribed motion): more pairs.
  for (std::size_t k = 0; k < end.size(); k += 3) end[k] -= 0.05;
  EXPECT_GT(expect_segment("obstacle moving", true), at_rest);
  // Both move.
  std::uniform_real_distribution<double> u(-0.02, 0.02);
  for (int v = 0; v < nb; ++v)
    for (int c = 0; c < 3; ++c) p[3 * node[v] + c] = u(rng);
  expect_segment("body and obstacle moving", true);

  // Prescribed rows need prescribed positions.
  Candidates none;
  EXPECT_NE(error_of([&] { search.find_candidates_on_segment(x_device.data(), p_device.data(), 0.01, &none); }), "");
  // kFaceDecides needs owned_face.
  d.owned_face.clear();
  EXPECT_NE(error_of([&] { search.upload(d); }), "");
}

}  // namespace
}  // namespace dipc::contact
