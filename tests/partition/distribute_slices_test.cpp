// distribute_slices under MPI (1, 2 and 3 ranks): with METIS it rebuilds distribute_mesh's
// parts field by field from slices; with PT-Scotch its parts are consistent with the input
// mesh and balanced; RCB cuts boxes where the geometry says, balanced to the element, whatever
// the numbering; slices round-trip; errors stop every rank; the host threads change nothing.
#include <gtest/gtest.h>
#include <petscsys.h>

#include <string>
#include <utility>

#include "box_mesh.hpp"
#include "distributed_mesh_checks.hpp"
#include "partition/distributed_mesh.hpp"
#include "partition/mesh_slice.hpp"
#include "partition/partition_error.hpp"
#include "threads/host_threads.hpp"

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
  for (const HexMesh& mesh :
       {test::structured_box(6, 4, 3), test::two_body_mesh(), mesh_with_orphan_node(),
        test::scattered_node_ids(test::two_body_mesh(), 3), test::scattered_node_ids(test::two_body_mesh(), 20)}) {
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
  if (size == 1)
    EXPECT_EQ(quality.edge_cut, 0);
  else
    EXPECT_GT(quality.edge_cut, 0);
  // The interior faces of a 6x4x3 and a 3x2x2 box: 5*4*3 + 6*3*3 + 6*4*2 + 2*2*2 + 3*1*2 + 3*2*1.
  EXPECT_EQ(quality.dual_edges, 60 + 54 + 48 + 8 + 6 + 6);
}

// Which rank holds each input element, the same on every rank.
std::vector<int> part_of_elements(const DistributedMesh& part, std::int64_t num_elements) {
  std::vector<int> owner(static_cast<std::size_t>(num_elements), -1);
  for (std::int64_t e : part.element_input_id) owner[static_cast<std::size_t>(e)] = test::rank_of(PETSC_COMM_WORLD);
  MPI_Allreduce(MPI_IN_PLACE, owner.data(), static_cast<int>(owner.size()), MPI_INT, MPI_MAX, PETSC_COMM_WORLD);
  return owner;
}

// An 18x10x8 box of unit hexes (1440 elements): x is the longest side, so 2 parts are x < 9 and
// x > 9 (a cut of 10 * 8 faces); 3 parts are x < 6 (480 elements), then the 12x10x8 rest cut
// at x = 12 (another 80 faces). The same along z for an 8x10x18 box, and for a shuffled node
// numbering.
TEST(DistributeSlices, RcbCutsBoxesAcrossTheLongestSide) {
  const int size = test::size_of(PETSC_COMM_WORLD);
  const std::int64_t expected_cut[] = {0, 80, 160};
  const std::pair<HexMesh, int> boxes[] = {{test::structured_box(18, 10, 8), 0},
                                           {test::structured_box(8, 10, 18), 2},
                                           {test::scattered_node_ids(test::structured_box(18, 10, 8), 7), 0}};
  for (const auto& [mesh, axis] : boxes) {
    const bool root = test::rank_of(PETSC_COMM_WORLD) == 0;
    const MeshSlice slice = slice_whole_mesh(root ? mesh : HexMesh(), PETSC_COMM_WORLD);
    DistributeReport report;
    const DistributedMesh part = distribute_slices(slice, Partitioner::rcb, true, &report);
    test::expect_consistent_with(mesh, part);
    EXPECT_EQ(report.quality.edge_cut, expected_cut[size - 1]);
    EXPECT_EQ(report.quality.largest_part, 1440 / size);
    EXPECT_EQ(report.quality.smallest_part, 1440 / size);
    // Every element of part p lies in the slab 18 p / size < x < 18 (p + 1) / size (x along `axis`).
    const std::vector<int> owner = part_of_elements(part, 1440);
    for (std::size_t e = 0; e < mesh.hexes.size(); ++e) {
      double x = 0;
      for (std::int64_t n : mesh.hexes[e]) x += mesh.nodes[static_cast<std::size_t>(n)][axis] / 8;
      EXPECT_EQ(owner[e], static_cast<int>(x * size / 18)) << "element " << e << " at " << x << " along axis " << axis;
    }
  }
}

// Cuts through a layer of elements with equal coordinates (7x3x2: 2 parts take 21 elements
// each, 3.5 of the 6-element x layers) are filled by input id, so parts differ by at most one
// element.
TEST(DistributeSlices, RcbBalancesToTheElement) {
  const int size = test::size_of(PETSC_COMM_WORLD);
  const HexMesh mesh = test::two_body_mesh();  // 72 + 12 elements, two bodies apart
  for (const HexMesh& m : {test::structured_box(7, 3, 2), mesh}) {
    const bool root = test::rank_of(PETSC_COMM_WORLD) == 0;
    const MeshSlice slice = slice_whole_mesh(root ? m : HexMesh(), PETSC_COMM_WORLD);
    DistributeReport report;
    const DistributedMesh part = distribute_slices(slice, Partitioner::rcb, true, &report);
    test::expect_consistent_with(m, part);
    const std::int64_t n = static_cast<std::int64_t>(m.hexes.size());
    EXPECT_LE(report.quality.largest_part - report.quality.smallest_part, 1)
        << n << " elements on " << size << " ranks";
    EXPECT_EQ(report.quality.largest_part, (n + size - 1) / size);
  }
}

TEST(DistributeSlices, QualityCountsTheCutFaces) {
  // A 12x1x1 bar: element i touches i + 1 through one face, so the cut is the number of i
  // whose part differs from i + 1's, counted here from the parts the ranks received.
  const int n = 12;
  const HexMesh mesh = test::structured_box(n, 1, 1);
  const bool root = test::rank_of(PETSC_COMM_WORLD) == 0;
  const MeshSlice slice = slice_whole_mesh(root ? mesh : HexMesh(), PETSC_COMM_WORLD);
  for (Partitioner p : {Partitioner::metis, Partitioner::ptscotch, Partitioner::rcb}) {
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

// The partition's loops on 1 and on 4 host threads: the same parts, field by field, and the same
// quality report. The meshes are large enough (27,000 and 16,000 elements) for several chunks
// per loop, and one has scattered node ids (TouchedNodes' sorted path).
TEST(DistributeSlices, HostThreadsGiveTheSameParts) {
  const bool root = test::rank_of(PETSC_COMM_WORLD) == 0;
  for (const HexMesh& mesh :
       {test::structured_box(30, 30, 30),
        test::scattered_node_ids(
            test::concatenate(test::structured_box(25, 20, 20), test::structured_box(10, 10, 10, {0, 0, 21}, 1)), 7)}) {
    const MeshSlice slice = slice_whole_mesh(root ? mesh : HexMesh(), PETSC_COMM_WORLD);
    for (Partitioner p : {Partitioner::metis, Partitioner::rcb}) {
      DistributeReport one, four;
      set_host_threads(1);
      const DistributedMesh expected = distribute_slices(slice, p, true, &one);
      set_host_threads(4);
      const DistributedMesh part = distribute_slices(slice, p, true, &four);
      set_host_threads(1);
      test::expect_identical(expected, part);
      EXPECT_EQ(one.quality.edge_cut, four.quality.edge_cut);
      EXPECT_EQ(one.quality.dual_edges, four.quality.dual_edges);
    }
  }
}

// A face of three elements late in a large mesh: 4 threads name the same elements as one.
TEST(DistributeSlices, HostThreadsReportTheSameSharedFace) {
  HexMesh mesh = test::structured_box(30, 30, 20);
  const std::size_t copied = mesh.hexes.size() - 100;
  mesh.hexes.push_back(mesh.hexes[copied]);
  mesh.body.push_back(0);
  const bool root = test::rank_of(PETSC_COMM_WORLD) == 0;
  const MeshSlice slice = slice_whole_mesh(root ? mesh : HexMesh(), PETSC_COMM_WORLD);
  std::string messages[2];
  for (int threads : {1, 4}) {
    set_host_threads(threads);
    try {
      distribute_slices(slice, Partitioner::metis);
      ADD_FAILURE() << "expected PartitionError";
    } catch (const PartitionError& e) {
      messages[threads == 4] = e.what();
    }
  }
  set_host_threads(1);
  EXPECT_NE(messages[0].find(", " + std::to_string(copied) + ","), std::string::npos) << "[" << messages[0] << "]";
  EXPECT_EQ(messages[0], messages[1]);
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
