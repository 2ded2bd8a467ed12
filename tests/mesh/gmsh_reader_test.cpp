// Tests of read_gmsh on valid MSH 4.1 files (tests/mesh/data): nodes, connectivity,
// physical groups as node sets, sparse tags, parametric node blocks, skipped sections and
// lower-dimensional elements.
#include "mesh/gmsh_reader.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>

#include "mesh/hex8_reference.hpp"
#include "mesh_test_support.hpp"

namespace dipc {
namespace {

using test::mesh_data;

// Coordinates of the nodes of a set, for comparisons that do not depend on node order.
std::set<Vec3> coordinates_of(const HexMesh& mesh, const std::string& set) {
  std::set<Vec3> out;
  for (std::int64_t n : mesh.node_sets.at(set)) out.insert(mesh.nodes.at(n));
  return out;
}

void expect_sorted_unique(const HexMesh& mesh) {
  for (const auto& [name, ids] : mesh.node_sets) {
    EXPECT_TRUE(std::is_sorted(ids.begin(), ids.end())) << name;
    EXPECT_EQ(std::adjacent_find(ids.begin(), ids.end()), ids.end()) << name;
  }
}

// Checks that element e's corners lie at the reference-cube corners of [lo, lo + 1]^3.
void expect_unit_cube_element(const HexMesh& mesh, std::size_t e, const Vec3& lo) {
  for (int a = 0; a < 8; ++a) {
    const Vec3& x = mesh.nodes[mesh.hexes[e][a]];
    EXPECT_EQ(x[0], lo[0] + 0.5 * (1 + hex8::corner_xi(a))) << "element " << e << " corner " << a;
    EXPECT_EQ(x[1], lo[1] + 0.5 * (1 + hex8::corner_eta(a))) << "element " << e << " corner " << a;
    EXPECT_EQ(x[2], lo[2] + 0.5 * (1 + hex8::corner_zeta(a))) << "element " << e << " corner " << a;
  }
}

TEST(GmshReader, BlockWithNamedPhysicalGroups) {
  const HexMesh mesh = read_gmsh(mesh_data("block_2x1x1.msh"), 3);
  ASSERT_EQ(mesh.num_nodes(), 12u);
  ASSERT_EQ(mesh.num_elements(), 2u);
  EXPECT_EQ(mesh.body, (std::vector<int>{3, 3}));
  // Nodes keep the file's order across blocks: tags 1, 4, 7, 10, 3, ... .
  EXPECT_EQ(mesh.nodes[0], (Vec3{0, 0, 0}));
  EXPECT_EQ(mesh.nodes[1], (Vec3{0, 1, 0}));
  EXPECT_EQ(mesh.nodes[4], (Vec3{2, 0, 0}));
  EXPECT_EQ(mesh.nodes[8], (Vec3{1, 0, 0}));
  expect_unit_cube_element(mesh, 0, {0, 0, 0});
  expect_unit_cube_element(mesh, 1, {1, 0, 0});
  EXPECT_NEAR(test::mesh_volume(mesh), 2.0, 1e-14);

  ASSERT_EQ(mesh.node_sets.size(), 3u);
  EXPECT_EQ(coordinates_of(mesh, "clamp"), (std::set<Vec3>{{0, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0, 1, 1}}));
  EXPECT_EQ(coordinates_of(mesh, "load"), (std::set<Vec3>{{2, 0, 0}, {2, 1, 0}, {2, 0, 1}, {2, 1, 1}}));
  EXPECT_EQ(mesh.node_sets.at("solid").size(), 12u);
  expect_sorted_unique(mesh);
}

TEST(GmshReader, UnnamedGroupsAreNamedByTag) {
  const HexMesh mesh = read_gmsh(mesh_data("unnamed_group.msh"), 0);
  ASSERT_EQ(mesh.num_elements(), 1u);
  ASSERT_EQ(mesh.node_sets.size(), 2u);
  EXPECT_EQ(coordinates_of(mesh, "physical_7"), (std::set<Vec3>{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}));
  EXPECT_EQ(mesh.node_sets.at("physical_8"), (std::vector<std::int64_t>{0, 1, 2, 3, 4, 5, 6, 7}));
}

TEST(GmshReader, SparseTagsParametricBlocksAndUnknownSections) {
  // Node tags 10..100000 out of order (beyond the dense tag range, so looked up by hash),
  // parametric coordinates after x y z, a $Comments section whose text names "$Nodes", and
  // a trailing $Periodic section.
  const HexMesh mesh = read_gmsh(mesh_data("sparse_tags.msh"), 1);
  ASSERT_EQ(mesh.num_nodes(), 8u);
  ASSERT_EQ(mesh.num_elements(), 1u);
  expect_unit_cube_element(mesh, 0, {0, 0, 0});
  // Node 0 is the file's first node (tag 100000); node 4 the first of the volume block.
  EXPECT_EQ(mesh.nodes[0], (Vec3{0, 0, 0}));
  EXPECT_EQ(mesh.nodes[4], (Vec3{1, 1, 1}));
  EXPECT_EQ(mesh.hexes[0][0], 0);
  EXPECT_EQ(mesh.hexes[0][6], 4);
  ASSERT_EQ(mesh.node_sets.size(), 1u);
  EXPECT_EQ(mesh.node_sets.at("cube").size(), 8u);
}

TEST(GmshReader, LowerDimensionalElementsOnlyFeedNodeSets) {
  const HexMesh mesh = read_gmsh(mesh_data("mixed_elements.msh"), 0);
  ASSERT_EQ(mesh.num_nodes(), 12u);
  ASSERT_EQ(mesh.num_elements(), 2u);  // the point, lines and triangles are not elements
  expect_unit_cube_element(mesh, 0, {0, 0, 0});
  expect_unit_cube_element(mesh, 1, {1, 0, 0});
  ASSERT_EQ(mesh.node_sets.size(), 4u);
  EXPECT_EQ(coordinates_of(mesh, "corner"), (std::set<Vec3>{{0, 0, 0}}));
  EXPECT_EQ(coordinates_of(mesh, "edge"), (std::set<Vec3>{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}}));
  EXPECT_EQ(coordinates_of(mesh, "right"), (std::set<Vec3>{{2, 0, 0}, {2, 1, 0}, {2, 0, 1}, {2, 1, 1}}));
  EXPECT_EQ(mesh.node_sets.at("solid").size(), 12u);
  expect_sorted_unique(mesh);
}

TEST(GmshReader, FileWrittenByGmsh) {
  // gmsh_box.msh is Gmsh's own output for gmsh_box.geo: per-entity node blocks, point and
  // curve entities, trailing spaces, physical groups of every dimension.
  const HexMesh mesh = read_gmsh(mesh_data("gmsh_box.msh"), 0);
  ASSERT_EQ(mesh.num_nodes(), 4u * 3u * 3u);
  ASSERT_EQ(mesh.num_elements(), 3u * 2u * 2u);
  EXPECT_NEAR(test::mesh_volume(mesh), 3.0, 1e-13);
  for (std::size_t e = 0; e < mesh.num_elements(); ++e) {
    double X[24];
    test::element_coordinates(mesh, e, X);
    // Gmsh writes transfinite node positions with round-off (0.9999999999998), hence 1e-12.
    EXPECT_NEAR(hex8::min_jacobian_determinant(X), 1.0 * 0.5 * 0.5 / 8, 1e-12) << "element " << e;
  }
  ASSERT_EQ(mesh.node_sets.size(), 5u);
  auto nodes_where = [&](auto predicate) {
    std::set<Vec3> out;
    for (const Vec3& x : mesh.nodes)
      if (predicate(x)) out.insert(x);
    return out;
  };
  EXPECT_EQ(coordinates_of(mesh, "bottom"), nodes_where([](const Vec3& x) { return x[2] == 0; }));
  EXPECT_EQ(coordinates_of(mesh, "physical_7"), nodes_where([](const Vec3& x) { return x[2] == 1; }));
  EXPECT_EQ(coordinates_of(mesh, "front_edge"), nodes_where([](const Vec3& x) { return x[1] == 0 && x[2] == 0; }));
  EXPECT_EQ(coordinates_of(mesh, "origin"), (std::set<Vec3>{{0, 0, 0}}));
  EXPECT_EQ(mesh.node_sets.at("solid").size(), mesh.num_nodes());
  expect_sorted_unique(mesh);
}

}  // namespace
}  // namespace dipc
