// The dipc-voxelize program: a closed OBJ and a binary STL become MSH files that read_gmsh
// reads with the groups the tool promises; bad input and bad arguments exit with status 1
// and a message naming the problem.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdio>
#include <fstream>
#include <sstream>

#include "mesh/gmsh_reader.hpp"
#include "mesh_test_support.hpp"

namespace dipc {
namespace {

struct Outcome {
  int status;
  std::string output;  // stdout and stderr
};

Outcome voxelize(const std::string& arguments) {
  const std::string command = std::string(DIPC_VOXELIZE) + " " + arguments + " 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  Outcome o{-1, ""};
  if (!pipe) return o;
  char buffer[4096];
  std::size_t n;
  while ((n = fread(buffer, 1, sizeof buffer, pipe)) > 0) o.output.append(buffer, n);
  const int raw = pclose(pipe);
  o.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  return o;
}

TEST(VoxelizeCli, ObjToMshWithGroups) {
  const std::string out = ::testing::TempDir() + "cube_voxels.msh";
  const Outcome o = voxelize(test::mesh_data("surfaces/unit_cube_quads.obj") + " " + out +
                             " --resolution 5 --group lid -1 -1 0.99 2 2 2");
  ASSERT_EQ(o.status, 0) << o.output;
  EXPECT_NE(o.output.find("grid 5 x 5 x 5, cell size 0.2; 125 hexahedra, 216 nodes, 150 boundary "
                          "quads; volume 1 (surface encloses 1, +0.000%)"),
            std::string::npos)
      << o.output;
  const HexMesh mesh = read_gmsh(out, 0);
  EXPECT_EQ(mesh.hexes.size(), 125u);
  EXPECT_NEAR(test::mesh_volume(mesh), 1.0, 1e-13);
  EXPECT_EQ(mesh.node_sets.at("solid").size(), 216u);
  EXPECT_EQ(mesh.node_sets.at("boundary").size(), 216u - 64u);  // all but the 4^3 interior
  EXPECT_EQ(mesh.node_sets.at("lid").size(), 36u);              // the z = 1 layer, 6 x 6
  for (std::int64_t v : mesh.node_sets.at("lid")) EXPECT_DOUBLE_EQ(mesh.nodes[v][2], 1.0);
}

TEST(VoxelizeCli, BinaryStlByCellSize) {
  // The tetrahedron (0.5,0.5,0.5) + 2 * {0, e_x, e_y, e_z}: volume 4/3.
  const std::string out = ::testing::TempDir() + "tetra_voxels.msh";
  const Outcome o = voxelize(test::mesh_data("surfaces/tetrahedron_binary.stl") + " " + out + " --cell-size 0.05");
  ASSERT_EQ(o.status, 0) << o.output;
  const HexMesh mesh = read_gmsh(out, 0);
  EXPECT_NEAR(test::mesh_volume(mesh), 4.0 / 3, 0.05);
}

TEST(VoxelizeCli, SnapKeepsTheMeshReadable) {
  const std::string stl = test::mesh_data("surfaces/tetrahedron_binary.stl");
  const std::string plain = ::testing::TempDir() + "tetra_plain.msh";
  const std::string snapped = ::testing::TempDir() + "tetra_snapped.msh";
  ASSERT_EQ(voxelize(stl + " " + plain + " --cell-size 0.1").status, 0);
  const Outcome o = voxelize(stl + " " + snapped + " --cell-size 0.1 --snap");
  ASSERT_EQ(o.status, 0) << o.output;
  EXPECT_NE(o.output.find("boundary nodes"), std::string::npos) << o.output;
  const HexMesh a = read_gmsh(plain, 0), b = read_gmsh(snapped, 0);  // check_mesh: det J > 0
  ASSERT_EQ(a.hexes, b.hexes);                                       // same cells, some nodes moved
  ASSERT_EQ(a.nodes.size(), b.nodes.size());
  std::size_t moved = 0;
  for (std::size_t v = 0; v < a.nodes.size(); ++v) moved += a.nodes[v] != b.nodes[v];
  EXPECT_GT(moved, 0u);
  // The tetrahedron's volume is 4/3; the staircase of 0.1 cells misses it by up to ~A h.
  EXPECT_NEAR(test::mesh_volume(b), 4.0 / 3, 0.1);
}

TEST(VoxelizeCli, BadInputExitsWithStatusOne) {
  const std::string open = ::testing::TempDir() + "open_square.obj";
  std::ofstream(open) << "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n";
  const std::string out = ::testing::TempDir() + "never.msh";
  struct Case {
    std::string arguments, fragment;
  };
  const Case cases[] = {
      {open + " " + out + " --resolution 4", "dipc-voxelize: error: " + open + ": the surface is not closed: edge ("},
      {test::mesh_data("surfaces/unit_cube_quads.obj") + " " + out, "give exactly one of --resolution and --cell-size"},
      {test::mesh_data("surfaces/unit_cube_quads.obj") + " " + out + " --resolution 0",
       "--resolution: '0' is not an integer in [1, 100000]"},
      {test::mesh_data("surfaces/unit_cube_quads.obj") + " " + out + " --cell-size -1", "--cell-size must be positive"},
      {test::mesh_data("surfaces/unit_cube_quads.obj") + " " + out + " --resolution 4 --group far 5 5 5 6 6 6",
       "--group far: no boundary face of the mesh lies in its box"},
      {test::mesh_data("surfaces/unit_cube_quads.obj") + " " + out + " --resolution 4 --bogus",
       "unknown option --bogus"},
      {"missing.stl " + out + " --resolution 4", "missing.stl: cannot open file"},
  };
  for (const Case& c : cases) {
    const Outcome o = voxelize(c.arguments);
    EXPECT_EQ(o.status, 1) << c.arguments << "\n" << o.output;
    EXPECT_NE(o.output.find(c.fragment), std::string::npos) << c.arguments << "\n" << o.output;
  }
}

}  // namespace
}  // namespace dipc
