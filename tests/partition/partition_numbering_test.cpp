// number_partition / local_nodes_of_part on a hand-made partition of a 3x1x1 beam, where the
// expected ownership and numbering can be written down, plus untouched nodes and bad input.
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "box_mesh.hpp"
#include "partition/partition_error.hpp"
#include "partition/partition_numbering.hpp"

namespace dipc {
namespace {

// Node ids of the 3x1x1 beam's cross-section at x = i (4 nodes, increasing id).
std::vector<std::int64_t> beam_layer(int i) {
  std::vector<std::int64_t> ids;
  for (int k = 0; k <= 1; ++k) {
    for (int j = 0; j <= 1; ++j) ids.push_back(i + 4 * (j + 2 * k));
  }
  return ids;
}

TEST(PartitionNumbering, LowestPartOwnsSharedNodesAndRangesAreContiguous) {
  // Elements 0 and 2 (the beam's ends) in part 1, the middle element 1 in part 0: part 0
  // touches layers 1 and 2 and owns them; part 1 owns layers 0 and 3 and sees 1, 2 as ghosts.
  const HexMesh mesh = test::structured_box(3, 1, 1);
  const PartitionNumbering numbering = number_partition(mesh, {1, 0, 1}, 2);

  EXPECT_EQ(numbering.node_offset, (std::vector<std::int64_t>{0, 8, 16}));
  EXPECT_EQ(numbering.element_offset, (std::vector<std::int64_t>{0, 1, 3}));
  EXPECT_EQ(numbering.elements_by_part, (std::vector<std::int64_t>{1, 0, 2}));
  EXPECT_EQ(numbering.num_global_nodes(), 16);
  EXPECT_EQ(numbering.num_global_elements(), 3);

  for (int layer = 0; layer <= 3; ++layer) {
    const int owner = (layer == 1 || layer == 2) ? 0 : 1;
    for (std::int64_t node : beam_layer(layer)) EXPECT_EQ(numbering.node_owner[node], owner);
  }
  // Within a part, global ids follow increasing input id: input ids of part 0's nodes,
  // sorted, get 0..7 and part 1's get 8..15.
  std::vector<std::int64_t> owned0;
  std::vector<std::int64_t> owned1;
  for (std::int64_t node = 0; node < 16; ++node) {
    (node % 4 == 1 || node % 4 == 2 ? owned0 : owned1).push_back(node);
  }
  for (std::size_t i = 0; i < owned0.size(); ++i) {
    EXPECT_EQ(numbering.node_global_id[owned0[i]], static_cast<std::int64_t>(i));
    EXPECT_EQ(numbering.node_global_id[owned1[i]], static_cast<std::int64_t>(8 + i));
  }

  EXPECT_EQ(local_nodes_of_part(mesh, numbering, 0), owned0);
  // Part 1: owned nodes first (layers 0 and 3 by input id), then the ghosts (layers 1 and 2)
  // by global id, which is their input order since part 0 numbered them increasingly.
  std::vector<std::int64_t> expected1 = owned1;
  expected1.insert(expected1.end(), owned0.begin(), owned0.end());
  EXPECT_EQ(local_nodes_of_part(mesh, numbering, 1), expected1);
}

TEST(PartitionNumbering, OwnershipFollowsTheLowestTouchingPart) {
  // One element per part along the beam: layer 1 is shared by parts 0 and 1 (owner 0),
  // layer 2 by parts 1 and 2 (owner 1).
  const HexMesh mesh = test::structured_box(3, 1, 1);
  const PartitionNumbering numbering = number_partition(mesh, {0, 1, 2}, 3);
  for (std::int64_t node : beam_layer(1)) EXPECT_EQ(numbering.node_owner[node], 0);
  for (std::int64_t node : beam_layer(2)) EXPECT_EQ(numbering.node_owner[node], 1);
  EXPECT_EQ(numbering.node_offset, (std::vector<std::int64_t>{0, 8, 12, 16}));

  std::vector<std::int64_t> expected1 = beam_layer(2);
  const std::vector<std::int64_t> ghosts = beam_layer(1);
  expected1.insert(expected1.end(), ghosts.begin(), ghosts.end());
  EXPECT_EQ(local_nodes_of_part(mesh, numbering, 1), expected1);
}

TEST(PartitionNumbering, PartMayOwnNothingOrHoldNothing) {
  // Part 1 holds the middle element, whose nodes part 0 also touches: it owns no node and
  // all its local nodes are ghosts (global ids = input ids here, since part 0 owns all).
  const HexMesh mesh = test::structured_box(3, 1, 1);
  const PartitionNumbering ghosts_only = number_partition(mesh, {0, 1, 0}, 2);
  EXPECT_EQ(ghosts_only.node_offset, (std::vector<std::int64_t>{0, 16, 16}));
  std::vector<std::int64_t> expected1 = beam_layer(1);
  const std::vector<std::int64_t> layer2 = beam_layer(2);
  expected1.insert(expected1.end(), layer2.begin(), layer2.end());
  std::sort(expected1.begin(), expected1.end());
  EXPECT_EQ(local_nodes_of_part(mesh, ghosts_only, 1), expected1);

  // Part 2 of 3 receives no element at all.
  const PartitionNumbering empty_part = number_partition(mesh, {0, 0, 1}, 3);
  EXPECT_EQ(empty_part.node_offset, (std::vector<std::int64_t>{0, 12, 16, 16}));
  EXPECT_EQ(empty_part.element_offset, (std::vector<std::int64_t>{0, 2, 3, 3}));
  EXPECT_TRUE(local_nodes_of_part(mesh, empty_part, 2).empty());
}

TEST(PartitionNumbering, UntouchedNodesGetNoOwnerAndNoGlobalId) {
  HexMesh mesh = test::structured_box(2, 1, 1);
  mesh.nodes.push_back({9, 9, 9});
  const PartitionNumbering numbering = number_partition(mesh, {0, 1}, 2);
  EXPECT_EQ(numbering.node_owner.back(), -1);
  EXPECT_EQ(numbering.node_global_id.back(), -1);
  EXPECT_EQ(numbering.num_global_nodes(), 12);
}

TEST(PartitionNumbering, RejectsInconsistentPartitions) {
  const HexMesh mesh = test::structured_box(2, 1, 1);
  EXPECT_THROW(number_partition(mesh, {0}, 2), PartitionError);
  EXPECT_THROW(number_partition(mesh, {0, 2}, 2), PartitionError);
  EXPECT_THROW(number_partition(mesh, {0, -1}, 2), PartitionError);
  HexMesh broken = mesh;
  broken.hexes[0][0] = -3;
  EXPECT_THROW(number_partition(broken, {0, 0}, 1), PartitionError);
}

}  // namespace
}  // namespace dipc
