// Tests of HexMesh::append: node id shift, concatenated bodies and sets, name clashes.
#include <gtest/gtest.h>

#include "mesh/box_generator.hpp"
#include "mesh/mesh_checks.hpp"
#include "mesh/mesh_error.hpp"

namespace dipc {
namespace {

TEST(HexMeshAppend, ShiftsNodeIdsAndKeepsSets) {
  HexMesh mesh = generate_box({1, 1, 1}, {2, 1, 1}, {0, 0, 0}, 0, "left");
  const HexMesh right = generate_box({1, 1, 1}, {1, 1, 1}, {3, 0, 0}, 1, "right");
  const auto offset = static_cast<std::int64_t>(mesh.num_nodes());
  const auto left_elements = mesh.num_elements();
  mesh.append(right);

  ASSERT_EQ(mesh.num_nodes(), static_cast<std::size_t>(offset) + right.num_nodes());
  ASSERT_EQ(mesh.num_elements(), left_elements + right.num_elements());
  ASSERT_EQ(mesh.body.size(), mesh.num_elements());
  EXPECT_EQ(mesh.body.front(), 0);
  EXPECT_EQ(mesh.body.back(), 1);
  for (int a = 0; a < 8; ++a) {
    EXPECT_EQ(mesh.hexes[left_elements][a], right.hexes[0][a] + offset);
    EXPECT_EQ(mesh.nodes[mesh.hexes[left_elements][a]], right.nodes[right.hexes[0][a]]);
  }
  EXPECT_EQ(mesh.node_sets.size(), 14u);
  const auto& xmax = mesh.node_sets.at("right.xmax");
  ASSERT_EQ(xmax.size(), right.node_sets.at("right.xmax").size());
  for (std::size_t i = 0; i < xmax.size(); ++i) EXPECT_EQ(xmax[i], right.node_sets.at("right.xmax")[i] + offset);
  EXPECT_EQ(mesh.node_sets.at("left.xmin"),
            generate_box({1, 1, 1}, {2, 1, 1}, {0, 0, 0}, 0, "left").node_sets.at("left.xmin"));
  EXPECT_NO_THROW(check_mesh(mesh, "appended"));
}

TEST(HexMeshAppend, AppendingToAnEmptyMeshCopies) {
  HexMesh mesh;
  const HexMesh box = generate_box({1, 2, 3}, {1, 2, 3}, {0, 0, 0}, 0, "box");
  mesh.append(box);
  EXPECT_EQ(mesh.nodes, box.nodes);
  EXPECT_EQ(mesh.hexes, box.hexes);
  EXPECT_EQ(mesh.node_sets, box.node_sets);
}

TEST(HexMeshAppend, RejectsDuplicateSetNamesAndLeavesMeshUnchanged) {
  HexMesh mesh = generate_box({1, 1, 1}, {1, 1, 1}, {0, 0, 0}, 0, "box");
  const HexMesh before = mesh;
  const HexMesh other = generate_box({1, 1, 1}, {1, 1, 1}, {2, 0, 0}, 1, "box");
  try {
    mesh.append(other);
    FAIL() << "no MeshError";
  } catch (const MeshError& e) {
    EXPECT_NE(std::string(e.what()).find("'box"), std::string::npos) << e.what();
  }
  EXPECT_EQ(mesh.nodes, before.nodes);
  EXPECT_EQ(mesh.hexes, before.hexes);
  EXPECT_EQ(mesh.node_sets, before.node_sets);
}

TEST(HexMeshAppend, RejectsMissingBodyIds) {
  HexMesh mesh = generate_box({1, 1, 1}, {1, 1, 1}, {0, 0, 0}, 0, "a");
  HexMesh other = generate_box({1, 1, 1}, {1, 1, 1}, {2, 0, 0}, 1, "b");
  other.body.clear();
  EXPECT_THROW(mesh.append(other), MeshError);
}

}  // namespace
}  // namespace dipc
