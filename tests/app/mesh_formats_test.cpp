// Every MSH flavour through the scene mesh path (tests/mesh/data, written by Gmsh 4.8.4): the
// box of gmsh_box.geo, clamped by its physical surface "bottom" and swinging under sideways
// gravity for 5 steps, on the ranks of the test's communicator (CTest: 1 and 2). Each flavour
// must give the trajectory of the ASCII MSH 4.1 file on the same ranks, and, run on all ranks,
// the trajectory of rank 0 alone. Likewise a voxelised STL tetrahedron, written as dipc-voxelize
// writes it. And dipc's HDF5 mesh file, read in slices: converted from the ASCII MSH 4.1 file by
// dipc-mesh-convert's code it gives that file's trajectory bit for bit, and so does the output
// of a run used as the next run's mesh (its /mesh group and selections).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "app/simulation.hpp"
#include "io/scene.hpp"
#include "mesh/boundary_faces.hpp"
#include "mesh/gmsh_writer.hpp"
#include "mesh/triangle_surface_reader.hpp"
#include "mesh/voxelizer.hpp"
#include "support/source_tree.hpp"
#include "tools/mesh_convert.hpp"

namespace dipc {
namespace {

// The body "box" from `mesh_file`, clamped by its node set `clamped`.
Scene box_scene(const std::string& mesh_file, const std::string& clamped = "bottom") {
  const std::string text = R"({"materials": [{"name": "rubber", "E": 1e5, "nu": 0.3, "rho": 1000}],)"
                           R"( "geometry": [{"name": "box", "mesh": ")" +
                           mesh_file +
                           R"(", "material": "rubber"}],)"
                           R"( "boundary_conditions": {"gravity": [0, -9.81, -9.81],)"
                           R"( "dirichlet": [{"selection": "box.)" +
                           clamped +
                           R"(", "type": "fixed"}]},)"
                           R"( "time": {"dt": 0.02, "steps": 5}, "contact": {"enabled": false}})";
  return parse_scene_text(text, "mesh_formats_test", dipc::test::source_dir() + "/tests/mesh/data");
}

RunResult run(const Scene& scene, MPI_Comm comm, bool setup_only = false, const std::string& output = "") {
  RunOptions options;
  options.write_output = !output.empty();
  options.output_dir = output;
  options.quiet = true;
  options.report = false;
  options.velocity_tol = 1e-10;
  options.setup_only = setup_only;
  RunResult result;
  EXPECT_EQ(run_scene(scene, comm, options, &result), 0);
  EXPECT_TRUE(result.failure.empty()) << result.failure;
  return result;
}

// max |a - b| / max |b - reference| over the displacements from `reference`.
double relative_difference(const std::vector<double>& a, const std::vector<double>& b,
                           const std::vector<double>& reference) {
  EXPECT_EQ(a.size(), b.size());
  double diff = 0, norm = 0;
  for (std::size_t i = 0; i < a.size() && i < b.size(); ++i) {
    diff = std::max(diff, std::abs(a[i] - b[i]));
    norm = std::max(norm, std::abs(b[i] - reference[i]));
  }
  EXPECT_GT(norm, 1e-4) << "the box did not move: the comparison would be vacuous";
  return diff / norm;
}

class MeshFormats : public ::testing::TestWithParam<const char*> {};

TEST_P(MeshFormats, SameTrajectoryAsAscii41AndAsOneRank) {
  PetscOptionsSetValue(nullptr, "-ksp_rtol", "1e-13");
  PetscOptionsSetValue(nullptr, "-ksp_atol", "1e-50");
  MPI_Comm world = PETSC_COMM_WORLD;
  int rank;
  MPI_Comm_rank(world, &rank);

  const Scene ascii41 = box_scene("gmsh_box.msh");
  const Scene scene = box_scene(GetParam());
  const RunResult reference_run = run(ascii41, world);
  const RunResult parallel = run(scene, world);

  MPI_Comm self;
  MPI_Comm_split(world, rank == 0 ? 0 : MPI_UNDEFINED, 0, &self);
  if (rank == 0) {
    const RunResult rest = run(scene, self, true);
    const RunResult serial = run(scene, self);
    // ASCII and binary coordinates differ in the last bit (Gmsh's %.16g), so the flavours
    // agree to round-off, not bit for bit.
    const double vs_ascii = relative_difference(parallel.positions, reference_run.positions, rest.positions);
    const double vs_serial = relative_difference(parallel.positions, serial.positions, rest.positions);
    std::printf("%s: vs ASCII 4.1 %.3e, vs one rank %.3e\n", GetParam(), vs_ascii, vs_serial);
    EXPECT_LE(vs_ascii, 1e-9);
    EXPECT_LE(vs_serial, 1e-8);
    MPI_Comm_free(&self);
  }
  for (const char* o : {"-ksp_rtol", "-ksp_atol"}) PetscOptionsClearValue(nullptr, o);
}

INSTANTIATE_TEST_SUITE_P(GmshWritten, MeshFormats,
                         ::testing::Values("gmsh_box_msh22.msh", "gmsh_box_msh22_bin.msh", "gmsh_box_msh41_bin.msh"),
                         [](const auto& info) {
                           std::string n = info.param;
                           return n.substr(0, n.size() - 4);
                         });

// The converted HDF5 file on all ranks against the MSH file on all ranks (the same rows, so the
// same trajectory to the last bit) and against itself on rank 0 alone.
TEST(Hdf5Mesh, ConvertedMshGivesTheMshTrajectory) {
  PetscOptionsSetValue(nullptr, "-ksp_rtol", "1e-13");
  PetscOptionsSetValue(nullptr, "-ksp_atol", "1e-50");
  MPI_Comm world = PETSC_COMM_WORLD;
  int rank;
  MPI_Comm_rank(world, &rank);
  const std::string h5 = ::testing::TempDir() + "gmsh_box_converted.h5";
  convert_gmsh_to_mesh_file(world, dipc::test::source_dir() + "/tests/mesh/data/gmsh_box.msh", h5);
  const RunResult msh = run(box_scene("gmsh_box.msh"), world);
  const Scene scene = box_scene(h5);
  const RunResult parallel = run(scene, world);
  EXPECT_EQ(parallel.positions, msh.positions);
  MPI_Comm self;
  MPI_Comm_split(world, rank == 0 ? 0 : MPI_UNDEFINED, 0, &self);
  if (rank == 0) {
    const RunResult rest = run(scene, self, true);
    const RunResult serial = run(scene, self);
    const double vs_serial = relative_difference(parallel.positions, serial.positions, rest.positions);
    std::printf("converted HDF5 mesh: vs one rank %.3e\n", vs_serial);
    EXPECT_LE(vs_serial, 1e-8);
    MPI_Comm_free(&self);
  }
  for (const char* o : {"-ksp_rtol", "-ksp_atol"}) PetscOptionsClearValue(nullptr, o);
}

// A run's output file names the next run's mesh: its /mesh rows are the input rows, its
// selections the input's, so a run from it is the run from the MSH file.
TEST(Hdf5Mesh, OutputSeedsTheNextRun) {
  MPI_Comm world = PETSC_COMM_WORLD;
  const std::string dir = ::testing::TempDir() + "hdf5_mesh_seed";
  const RunResult first = run(box_scene("gmsh_box.msh"), world, false, dir);
  ASSERT_FALSE(first.xdmf_path.empty());
  std::string h5 = first.xdmf_path.substr(0, first.xdmf_path.size() - 4) + ".h5";
  const RunResult again = run(box_scene("gmsh_box.msh"), world);
  // The output's selections keep their scene names ("box.bottom"); the seeded body "box"
  // prefixes them again.
  const RunResult seeded = run(box_scene(h5, "box.bottom"), world);
  EXPECT_EQ(seeded.positions, again.positions);
}

// The binary STL tetrahedron (0.5,0.5,0.5) + 2 {0, e_x, e_y, e_z} voxelised at cell size 0.2
// (rank 0 writes the file), clamped by its boundary faces on the bottom layer.
TEST(VoxelisedMesh, RunsAndMatchesOneRank) {
  MPI_Comm world = PETSC_COMM_WORLD;
  int rank;
  MPI_Comm_rank(world, &rank);
  const std::string path = ::testing::TempDir() + "voxelised_tetrahedron.msh";
  if (rank == 0) {
    const HexMesh mesh = voxelize(read_triangle_surface(dipc::test::source_dir() +
                                                        "/tests/mesh/data/surfaces/tetrahedron_binary.stl"),
                                  0, 0.2);
    QuadGroup bottom{"base", {}};
    for (const BoundaryFace& f : extract_boundary_faces(mesh)) {
      if (f.face != 4) continue;  // zeta = -1: the faces looking down
      const auto local = hex_face_nodes(f.face);
      std::array<std::int64_t, 4> quad;
      for (int c = 0; c < 4; ++c) quad[c] = mesh.hexes[f.element][local[c]];
      if (mesh.nodes[quad[0]][2] < 0.6) bottom.quads.push_back(quad);
    }
    ASSERT_FALSE(bottom.quads.empty());
    write_gmsh(path, mesh, "solid", {bottom});
  }
  MPI_Barrier(world);
  PetscOptionsSetValue(nullptr, "-ksp_rtol", "1e-13");
  PetscOptionsSetValue(nullptr, "-ksp_atol", "1e-50");
  const Scene scene = box_scene(path, "base");
  const RunResult parallel = run(scene, world);
  MPI_Comm self;
  MPI_Comm_split(world, rank == 0 ? 0 : MPI_UNDEFINED, 0, &self);
  if (rank == 0) {
    const RunResult rest = run(scene, self, true);
    const RunResult serial = run(scene, self);
    EXPECT_GT(rest.positions.size(), 3u * 50u);  // a mesh of some size, not a single cell
    const double vs_serial = relative_difference(parallel.positions, serial.positions, rest.positions);
    std::printf("voxelised tetrahedron (%zu nodes): vs one rank %.3e\n", rest.positions.size() / 3, vs_serial);
    EXPECT_LE(vs_serial, 1e-8);
    MPI_Comm_free(&self);
  }
  for (const char* o : {"-ksp_rtol", "-ksp_atol"}) PetscOptionsClearValue(nullptr, o);
}

}  // namespace
}  // namespace dipc
