// distribute_slices under MPI (1, 2 and 3 ranks): with METIS it rebuilds distribute_mesh's
// parts field by field from slices; with PT-Scotch its parts are consistent with the input
// mesh and balanced; slices round-trip; errors stop every rank.
#include <gtest/gtest.h>
#include <petscsys.h>

#include <string>

#include "box_mesh.hpp"
#include "distributed_mesh_checks.hpp"
#include "partition/distributed_mesh.hpp"
#include "partition/mesh_slice.hpp"
#include "partition/partition_error.hpp"

namespace dipc {
namespace {

HexMesh mesh_with_orphan_node() {
  HexMesh mesh;
  mesh.nodes.push_back({-5, -5, -5});
  mesh.node_sets["with_orphan"] = {0, 1, 2};
  return test::concatenate(mesh, test::two_body_mesh());
}

TEST(DistributeSlices, SlicesRoundTrip) {
  const HexMesh mesh = test::two_body_mesh();
  const MeshSlice slice = slice_whole_mesh(test::rank_of(PETSC_COMM_WORLD) == 0 ? mesh : HexMesh(), PETSC_COMM_WORLD);
  check_slice_layout(slice);
  EXPECT_EQ(slice.num_global_nodes, static_cast<std::int64_t>(mesh.num_nodes()));
  const HexMesh back = gather_whole_mesh(slice);
  if (test::rank_of(PETSC_COMM_WORLD) == 0) {
    EXPECT_EQ(back.nodes, mesh.nodes);
    EXPECT_EQ(back.hexes, mesh.hexes);
    EXPECT_EQ(back.body, mesh.body);
    EXPECT_EQ(back.node_sets, mesh.node_sets);
  }
}

TEST(DistributeSlices, MetisGivesTheRootDistribution) {
  for (const HexMesh& mesh : {test::structured_box(6, 4, 3), test::two_body_mesh(), mesh_with_orphan_node(),
                              test::scattered_node_ids(test::two_body_mesh(), 3),
                              test::scattered_node_ids(test::two_body_mesh(), 20)}) {
    for (bool with_surface : {true, false}) {
      const bool root = test::rank_of(PETSC_COMM_WORLD) == 0;
      const DistributedMesh expected = distribute_mesh(root ? mesh : HexMesh(), PETSC_COMM_WORLD, with_surface);
      const MeshSlice slice = slice_whole_mesh(root ? mesh : HexMesh(), PETSC_COMM_WORLD);
      const DistributedMesh part = distribute_slices(slice, Partitioner::metis, with_surface);
      test::expect_identical(expected, part);
    }
  }
}

TEST(DistributeSlices, PtScotchPartsAreConsistentAndBalanced) {
  if (!ptscotch_available()) GTEST_SKIP() << "this PETSc has no PT-Scotch";
  const HexMesh mesh = test::two_body_mesh();
  const bool root = test::rank_of(PETSC_COMM_WORLD) == 0;
  const MeshSlice slice = slice_whole_mesh(root ? mesh : HexMesh(), PETSC_COMM_WORLD);
  DistributeReport report;
  const DistributedMesh first = distribute_slices(slice, Partitioner::ptscotch, true, &report);
  const PartitionQuality& quality = report.quality;
  test::expect_consistent_with(mesh, first);
  const int size = test::size_of(PETSC_COMM_WORLD);
  // 84 elements; PT-Scotch's default strategy allows a few percent of imbalance.
  EXPECT_LE(quality.imbalance, 1.15);
  EXPECT_GT(quality.smallest_part, 0);
  if (size == 1) EXPECT_EQ(quality.edge_cut, 0);
  else EXPECT_GT(quality.edge_cut, 0);
  // The interior faces of a 6x4x3 and a 3x2x2 box: 5*4*3 + 6*3*3 + 6*4*2 + 2*2*2 + 3*1*2 + 3*2*1.
  EXPECT_EQ(quality.dual_edges, 60 + 54 + 48 + 8 + 6 + 6);
}

TEST(DistributeSlices, QualityCountsTheCutFaces) {
  // A 12x1x1 bar: element i touches i + 1 through one face, so the cut is the number of i
  // whose part differs from i + 1's, counted here from the parts the ranks received.
  const int n = 12;
  const HexMesh mesh = test::structured_box(n, 1, 1);
  const bool root = test::rank_of(PETSC_COMM_WORLD) == 0;
  const MeshSlice slice = slice_whole_mesh(root ? mesh : HexMesh(), PETSC_COMM_WORLD);
  for (Partitioner p : {Partitioner::metis, Partitioner::ptscotch}) {
    if (p == Partitioner::ptscotch && !ptscotch_available()) continue;
    DistributeReport report;
    const DistributedMesh part = distribute_slices(slice, p, false, &report);
    const PartitionQuality& quality = report.quality;
    std::vector<int> owner(n, 0);
    for (std::int64_t e : part.element_input_id) owner[e] = test::rank_of(PETSC_COMM_WORLD);
    MPI_Allreduce(MPI_IN_PLACE, owner.data(), n, MPI_INT, MPI_MAX, PETSC_COMM_WORLD);
    std::int64_t cut = 0;
    for (int i = 0; i + 1 < n; ++i) cut += owner[i] != owner[i + 1];
    int largest = part.num_elements();
    MPI_Allreduce(MPI_IN_PLACE, &largest, 1, MPI_INT, MPI_MAX, PETSC_COMM_WORLD);
    const int size = test::size_of(PETSC_COMM_WORLD);
    EXPECT_EQ(quality.dual_edges, n - 1);
    EXPECT_EQ(quality.edge_cut, cut) << partitioner_name(p);
    EXPECT_GE(quality.edge_cut, size - 1) << partitioner_name(p);
    EXPECT_EQ(quality.largest_part, largest);
    EXPECT_DOUBLE_EQ(quality.imbalance, static_cast<double>(largest) * size / n);
  }
}

TEST(DistributeSlices, FaceOfThreeElementsThrowsOnEveryRank) {
  HexMesh mesh = test::structured_box(2, 1, 1);
  mesh.hexes.push_back(mesh.hexes[0]);  // a copy of element 0 shares all its faces
  mesh.body.push_back(0);
  const bool root = test::rank_of(PETSC_COMM_WORLD) == 0;
  const MeshSlice slice = slice_whole_mesh(root ? mesh : HexMesh(), PETSC_COMM_WORLD);
  try {
    distribute_slices(slice, Partitioner::metis);
    FAIL() << "expected PartitionError";
  } catch (const PartitionError& e) {
    EXPECT_NE(std::string(e.what()).find("3 elements share one face"), std::string::npos) << e.what();
  }
}

TEST(DistributeSlices, UnknownPartitionerIsNamed) {
  try {
    parse_partitioner("parmetis");
    FAIL();
  } catch (const PartitionError& e) {
    EXPECT_NE(std::string(e.what()).find("\"parmetis\""), std::string::npos);
  }
}

}  // namespace
}  // namespace dipc
