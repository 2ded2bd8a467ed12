// Generated boxes as slices (app/scene_slice.hpp), on the ranks of the test's communicator
// (CTest: 1, 2 and 3): every rank generates only its rows, and together they are the whole
// mesh generate_box and HexMesh::append give, bit for bit — coordinates, connectivity, bodies
// and node sets — whatever the cut between ranks (the rows of a rank start inside a grid row,
// a layer, or the next body).
// The same on 3 host threads, in chunks of a few rows.
#include <gtest/gtest.h>
#include <petscsys.h>

#include "app/scene_slice.hpp"
#include "io/scene.hpp"
#include "mesh/box_generator.hpp"
#include "partition/mesh_slice.hpp"
#include "threads/host_threads.hpp"

namespace dipc {
namespace {

// threads > 1: the rows are generated in chunks of a few rows on that many host threads.
void generated_boxes_are_generate_box_rows(int threads) {
  set_host_threads(threads, threads > 1 ? 1 : 0);
  // Odd resolutions and origins, so that rank cuts fall inside rows and coordinates are not
  // round numbers; a second box whose rows follow the first's.
  const Scene scene = parse_scene_text(
      R"({"materials": [{"name": "rubber", "E": 1e5, "nu": 0.3, "rho": 1000}],)"
      R"( "geometry": [{"name": "lower", "box": {"size": [0.7, 0.3, 0.2], "resolution": [7, 5, 3], "origin": [0.1, -0.2, 0.03]},)"
      R"(               "material": "rubber"},)"
      R"(              {"name": "upper", "box": {"size": [0.3, 0.3, 0.3], "resolution": [4, 3, 5], "origin": [0.2, -0.1, 0.5]},)"
      R"(               "material": "rubber"}],)"
      R"( "time": {"dt": 0.01, "steps": 1}})",
      "scene_slice_test", ".");
  const MeshSlice slice = build_scene_slice(scene, PETSC_COMM_WORLD);
  set_host_threads(1);
  check_slice_layout(slice);
  const HexMesh whole = gather_whole_mesh(slice);
  int rank = 0;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  if (rank != 0) return;
  HexMesh expected = generate_box({0.7, 0.3, 0.2}, {7, 5, 3}, {0.1, -0.2, 0.03}, 0, "lower");
  expected.append(generate_box({0.3, 0.3, 0.3}, {4, 3, 5}, {0.2, -0.1, 0.5}, 1, "upper"));
  ASSERT_EQ(whole.nodes.size(), expected.nodes.size());
  for (std::size_t n = 0; n < expected.nodes.size(); ++n)
    for (int c = 0; c < 3; ++c)
      ASSERT_EQ(whole.nodes[n][c], expected.nodes[n][c]) << "node " << n << " coordinate " << c;
  EXPECT_EQ(whole.hexes, expected.hexes);
  EXPECT_EQ(whole.body, expected.body);
  EXPECT_EQ(whole.node_sets, expected.node_sets);
}

TEST(SceneSlice, GeneratedBoxesAreGenerateBoxRows) { generated_boxes_are_generate_box_rows(1); }

TEST(SceneSlice, GeneratedBoxesOnThreadsAreGenerateBoxRows) { generated_boxes_are_generate_box_rows(3); }

}  // namespace
}  // namespace dipc
