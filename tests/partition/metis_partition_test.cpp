// partition_elements: trivial single part, valid and balanced METIS parts, face adjacency,
// determinism and the error messages for impossible requests.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "box_mesh.hpp"
#include "partition/metis_partition.hpp"
#include "partition/partition_error.hpp"

namespace dipc {
namespace {

TEST(MetisPartition, SinglePartIsAllZeros) {
  const HexMesh mesh = test::structured_box(6, 4, 3);
  const std::vector<int> part = partition_elements(mesh, 1);
  EXPECT_EQ(part, std::vector<int>(72, 0));
}

TEST(MetisPartition, PartsAreValidNonEmptyAndBalanced) {
  const HexMesh mesh = test::structured_box(6, 4, 3);
  for (int nparts : {2, 3, 4, 5}) {
    const std::vector<int> part = partition_elements(mesh, nparts);
    ASSERT_EQ(part.size(), mesh.num_elements());
    std::vector<int> count(nparts, 0);
    for (int p : part) {
      ASSERT_GE(p, 0);
      ASSERT_LT(p, nparts);
      ++count[p];
    }
    const double mean = 72.0 / nparts;
    for (int p = 0; p < nparts; ++p) {
      EXPECT_GE(count[p], 0.5 * mean) << "part " << p << " of " << nparts;
      EXPECT_LE(count[p], 1.5 * mean) << "part " << p << " of " << nparts;
    }
  }
}

TEST(MetisPartition, SameInputGivesSamePartition) {
  const HexMesh mesh = test::two_body_mesh();
  EXPECT_EQ(partition_elements(mesh, 3), partition_elements(mesh, 3));
}

TEST(MetisPartition, BeamSplitsIntoFaceConnectedHalves) {
  // A 4x1x1 beam's dual graph (face adjacency) is a path: the minimum cut into two equal
  // parts is the middle face. With ncommon < 4, edge/corner neighbours would not change a
  // path, so this also checks that elements sharing a face are seen as neighbours at all.
  const HexMesh mesh = test::structured_box(4, 1, 1);
  const std::vector<int> part = partition_elements(mesh, 2);
  EXPECT_EQ(part[0], part[1]);
  EXPECT_EQ(part[2], part[3]);
  EXPECT_NE(part[0], part[2]);
}

TEST(MetisPartition, MorePartsThanElementsThrows) {
  const HexMesh mesh = test::structured_box(2, 1, 1);
  try {
    partition_elements(mesh, 3);
    FAIL() << "expected PartitionError";
  } catch (const PartitionError& e) {
    EXPECT_NE(std::string(e.what()).find("more parts than elements"), std::string::npos) << e.what();
  }
  EXPECT_THROW(partition_elements(mesh, 0), PartitionError);
  EXPECT_THROW(partition_elements(HexMesh{}, 1), PartitionError);
}

TEST(MetisPartition, NodeIdOutsideMeshNamesTheElement) {
  HexMesh mesh = test::structured_box(3, 1, 1);
  mesh.hexes[1][6] = 1000;
  try {
    partition_elements(mesh, 2);
    FAIL() << "expected PartitionError";
  } catch (const PartitionError& e) {
    EXPECT_NE(std::string(e.what()).find("element 1 node 6 has id 1000"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace dipc
