// distribute_mesh under MPI (1, 2 and 3 ranks): consistency of every rank's part with the
// input mesh, balance, determinism, untouched nodes, and errors raised on every rank.
#include <gtest/gtest.h>
#include <petscsys.h>

#include <string>

#include "box_mesh.hpp"
#include "distributed_mesh_checks.hpp"
#include "partition/distributed_mesh.hpp"
#include "partition/partition_error.hpp"

namespace dipc {
namespace {

TEST(DistributeMesh, BoxPartsAreConsistent) {
  const HexMesh mesh = test::structured_box(6, 4, 3);
  const DistributedMesh part = test::distribute_from_root(mesh, PETSC_COMM_WORLD);
  test::expect_consistent_with(mesh, part);

  // With several ranks the box must actually be cut, so ghosts exist somewhere.
  int ghosts = part.num_ghost_nodes();
  MPI_Allreduce(MPI_IN_PLACE, &ghosts, 1, MPI_INT, MPI_SUM, PETSC_COMM_WORLD);
  if (test::size_of(PETSC_COMM_WORLD) > 1) {
    EXPECT_GT(ghosts, 0);
  } else {
    EXPECT_EQ(ghosts, 0);
  }
}

TEST(DistributeMesh, TwoBodyPartsAreConsistent) {
  const HexMesh mesh = test::two_body_mesh();
  test::expect_consistent_with(mesh, test::distribute_from_root(mesh, PETSC_COMM_WORLD));
}

TEST(DistributeMesh, BoxPartsAreBalanced) {
  const HexMesh mesh = test::structured_box(6, 4, 3);
  const DistributedMesh part = test::distribute_from_root(mesh, PETSC_COMM_WORLD);
  const double mean = 72.0 / test::size_of(PETSC_COMM_WORLD);
  EXPECT_GE(part.num_elements(), 0.5 * mean);
  EXPECT_LE(part.num_elements(), 1.5 * mean);
}

TEST(DistributeMesh, SameInputGivesSameParts) {
  const HexMesh mesh = test::two_body_mesh();
  const DistributedMesh first = test::distribute_from_root(mesh, PETSC_COMM_WORLD);
  const DistributedMesh second = test::distribute_from_root(mesh, PETSC_COMM_WORLD);
  test::expect_identical(first, second);
}

TEST(DistributeMesh, SelfCommunicatorKeepsInputNumbering) {
  // One part: owned nodes in increasing input id are the input numbering itself.
  const HexMesh mesh = test::structured_box(3, 2, 2);
  const DistributedMesh part = distribute_mesh(mesh, PETSC_COMM_SELF);
  test::expect_consistent_with(mesh, part);
  ASSERT_EQ(part.num_owned_nodes, static_cast<int>(mesh.num_nodes()));
  EXPECT_EQ(part.num_ghost_nodes(), 0);
  for (int i = 0; i < part.num_local_nodes(); ++i) {
    EXPECT_EQ(part.local_to_global[i], i);
    EXPECT_EQ(part.node_input_id[i], i);
  }
  ASSERT_EQ(part.num_elements(), static_cast<int>(mesh.num_elements()));
  for (int e = 0; e < part.num_elements(); ++e) {
    for (int k = 0; k < 8; ++k) EXPECT_EQ(part.elements[e][k], mesh.hexes[e][k]);
  }
}

TEST(DistributeMesh, UntouchedNodesAreLeftOut) {
  // Node 0 of this mesh belongs to no element (e.g. a Gmsh geometry point); it is dropped
  // from the numbering and from the node sets.
  HexMesh box = test::structured_box(6, 4, 3);
  HexMesh mesh;
  mesh.nodes.push_back({-5, -5, -5});
  mesh.node_sets["with_orphan"] = {0, 1, 2};
  mesh = test::concatenate(mesh, box);
  const DistributedMesh part = test::distribute_from_root(mesh, PETSC_COMM_WORLD);
  EXPECT_EQ(part.num_global_nodes, static_cast<std::int64_t>(box.num_nodes()));
  test::expect_consistent_with(mesh, part);
  for (std::int64_t input : part.node_input_id) EXPECT_NE(input, 0);
}

void expect_error_on_every_rank(const HexMesh& mesh, const std::string& expected) {
  try {
    test::distribute_from_root(mesh, PETSC_COMM_WORLD);
    ADD_FAILURE() << "expected PartitionError containing '" << expected << "'";
  } catch (const PartitionError& e) {
    EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
  }
}

TEST(DistributeMesh, InvalidMeshThrowsOnEveryRank) {
  HexMesh bad_node = test::structured_box(6, 4, 3);
  bad_node.hexes[5][3] = -1;
  expect_error_on_every_rank(bad_node, "element 5 node 3 has id -1");

  HexMesh bad_set = test::structured_box(6, 4, 3);
  bad_set.node_sets["box.xmin"].push_back(999);
  expect_error_on_every_rank(bad_set, "node set 'box.xmin' contains node id 999");

  HexMesh bad_body = test::structured_box(6, 4, 3);
  bad_body.body.pop_back();
  expect_error_on_every_rank(bad_body, "71 body ids for 72 elements");

  // Rank 0 extracts the boundary surface: a face of three elements stops it on every rank.
  HexMesh non_manifold = test::structured_box(6, 4, 3);
  non_manifold.hexes.push_back(non_manifold.hexes[1]);
  non_manifold.body.push_back(0);
  expect_error_on_every_rank(non_manifold, "3 elements share one face");

  // The communicator still works after an error.
  const HexMesh mesh = test::structured_box(2, 2, 2);
  test::expect_consistent_with(mesh, test::distribute_from_root(mesh, PETSC_COMM_WORLD));
}

TEST(DistributeMesh, MoreRanksThanElementsThrowsOnEveryRank) {
  if (test::size_of(PETSC_COMM_WORLD) < 2) GTEST_SKIP() << "needs at least 2 ranks";
  expect_error_on_every_rank(test::structured_box(1, 1, 1), "more parts than elements");
}

}  // namespace
}  // namespace dipc
