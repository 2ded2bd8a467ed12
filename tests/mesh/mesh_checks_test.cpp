// Tests of check_mesh (each rule on a one-element mesh broken on purpose) and
// bounding_box_diagonal.
#include "mesh/mesh_checks.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>

#include "mesh/box_generator.hpp"
#include "mesh/mesh_error.hpp"

namespace dipc {
namespace {

HexMesh unit_cube() { return generate_box({1, 1, 1}, {1, 1, 1}, {0, 0, 0}, 0, "cube"); }

// The message check_mesh throws for `mesh`, or "" if it accepts it.
std::string check_message(const HexMesh& mesh, const MeshSourceMap* map = nullptr) {
  try {
    check_mesh(mesh, "test-mesh", map);
  } catch (const MeshError& e) {
    return e.what();
  }
  return "";
}

void expect_rejected(const HexMesh& mesh, const std::vector<std::string>& fragments) {
  const std::string message = check_message(mesh);
  ASSERT_FALSE(message.empty()) << "check_mesh accepted the mesh";
  EXPECT_EQ(message.rfind("test-mesh: ", 0), 0u) << message;
  for (const auto& f : fragments) EXPECT_NE(message.find(f), std::string::npos) << message;
}

TEST(CheckMesh, AcceptsValidMeshes) {
  EXPECT_EQ(check_message(unit_cube()), "");
  EXPECT_EQ(check_message(generate_box({3, 1, 2}, {5, 2, 4}, {-1, -1, -1}, 3, "b")), "");
}

TEST(CheckMesh, DegeneracyIsRelativeToElementSize) {
  // A 1e-6 cube has det J = 1.25e-19, far below any absolute threshold, but is a perfect
  // element: it must pass.
  EXPECT_EQ(check_message(generate_box({1e-6, 1e-6, 1e-6}, {1, 1, 1}, {0, 0, 0}, 0, "tiny")), "");
}

TEST(CheckMesh, InvertedElement) {
  HexMesh mesh = unit_cube();
  auto& h = mesh.hexes[0];
  std::swap_ranges(h.begin(), h.begin() + 4, h.begin() + 4);  // top and bottom faces swapped
  expect_rejected(mesh, {"element 0 is inverted", "det J = -0.125"});
}

TEST(CheckMesh, InvertedCornerIsLocated) {
  // Pull corner 6 from (1,1,1) to (0.1,0.1,0.1): at corner 6, J = [x6 - x7, x6 - x5, x6 - x2]/2
  // has 0.1/2 on the diagonal and -0.9/2 off it, eigenvalues (0.1 - 2·0.9)/2 and (0.1 + 0.9)/2
  // (twice), so det J = -1.7/8 = -0.2125 there while the other corners stay positive.
  HexMesh mesh = unit_cube();
  mesh.nodes[mesh.hexes[0][6]] = {0.1, 0.1, 0.1};
  expect_rejected(mesh, {"element 0 is inverted", "at corner 6", "det J = -0.2125"});
}

TEST(CheckMesh, DegenerateElement) {
  HexMesh mesh = unit_cube();
  for (int a = 4; a < 8; ++a) mesh.nodes[mesh.hexes[0][a]][2] = 0.0;  // flattened to z = 0
  expect_rejected(mesh, {"element 0 is degenerate", "det J = 0"});
}

TEST(CheckMesh, NonFiniteCoordinate) {
  HexMesh mesh = unit_cube();
  mesh.nodes[3][1] = std::numeric_limits<double>::quiet_NaN();
  expect_rejected(mesh, {"node 3 has a non-finite y coordinate"});
  mesh.nodes[3][1] = 1.0;
  mesh.nodes[5][2] = -std::numeric_limits<double>::infinity();
  expect_rejected(mesh, {"node 5 has a non-finite z coordinate"});
}

TEST(CheckMesh, NodeIdOutOfRange) {
  HexMesh mesh = unit_cube();
  mesh.hexes[0][7] = 8;
  expect_rejected(mesh, {"element 0 refers to node id 8 out of range [0, 8)"});
  mesh.hexes[0][7] = -1;
  expect_rejected(mesh, {"element 0 refers to node id -1"});
}

TEST(CheckMesh, RepeatedNodeInElement) {
  HexMesh mesh = unit_cube();
  mesh.nodes.push_back({0, 1, 1});
  mesh.hexes[0][7] = mesh.hexes[0][2];  // node 3, at (1, 1, 0)
  expect_rejected(mesh, {"element 0 uses node 3 twice (corners 2 and 7)"});
}

TEST(CheckMesh, UnusedNode) {
  HexMesh mesh = unit_cube();
  mesh.nodes.push_back({5, 5, 5});
  expect_rejected(mesh, {"node 8 is not used by any element"});
}

TEST(CheckMesh, BodyIds) {
  HexMesh mesh = unit_cube();
  mesh.body[0] = -1;
  expect_rejected(mesh, {"element 0 has negative body id -1"});
  mesh.body.clear();
  expect_rejected(mesh, {"0 body ids for 1 elements"});
}

TEST(CheckMesh, EmptyMesh) { expect_rejected(HexMesh{}, {"no elements"}); }

TEST(CheckMesh, NodeSets) {
  HexMesh mesh = unit_cube();
  mesh.node_sets["bad"] = {0, 8};
  expect_rejected(mesh, {"node set 'bad'", "node id 8 out of range"});
  mesh.node_sets["bad"] = {2, 1};
  expect_rejected(mesh, {"node set 'bad' is not sorted and unique"});
  mesh.node_sets["bad"] = {1, 1};
  expect_rejected(mesh, {"node set 'bad' is not sorted and unique"});
}

TEST(CheckMesh, SourceMapNamesFileTagsAndLines) {
  HexMesh mesh = unit_cube();
  auto& h = mesh.hexes[0];
  std::swap_ranges(h.begin(), h.begin() + 4, h.begin() + 4);
  MeshSourceMap map;
  map.element_tags = {17};
  map.element_lines = {42};
  map.node_tags = {11, 12, 13, 14, 15, 16, 17, 18, 19};
  map.node_lines = {3, 4, 5, 6, 7, 8, 9, 10, 11};
  std::string message = check_message(mesh, &map);
  EXPECT_EQ(message.rfind("test-mesh:42: element 17 (hexahedron) is inverted", 0), 0u) << message;

  mesh = unit_cube();
  mesh.nodes.push_back({5, 5, 5});
  message = check_message(mesh, &map);
  EXPECT_EQ(message.rfind("test-mesh:11: node 19 is not used", 0), 0u) << message;
}

TEST(BoundingBoxDiagonal, OfBoxAndEmptyMesh) {
  EXPECT_DOUBLE_EQ(bounding_box_diagonal(generate_box({3, 4, 12}, {2, 3, 1}, {-7, 2, 5}, 0, "b")), 13.0);
  EXPECT_EQ(bounding_box_diagonal(HexMesh{}), 0.0);
}

}  // namespace
}  // namespace dipc
