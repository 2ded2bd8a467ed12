// The MSH flavours Gmsh writes — 4.1 and 2.2, ASCII and binary — read to the same mesh, on
// files written by Gmsh 4.8.4 (committed in data/) and, where a gmsh program was found at
// configure time, on files the installed gmsh writes now. Bad binary files (made by patching
// the committed ones at places the test finds) are rejected with byte offsets.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>

#include "mesh/gmsh_reader.hpp"
#include "mesh/mesh_error.hpp"
#include "mesh_test_support.hpp"

namespace dipc {
namespace {

using test::mesh_data;

void expect_same_mesh(const HexMesh& a, const HexMesh& b) {
  ASSERT_EQ(a.nodes.size(), b.nodes.size());
  // Gmsh writes ASCII coordinates with %.16g, one digit short of a round trip: ASCII and
  // binary files of one mesh differ in the last bit.
  for (std::size_t i = 0; i < a.nodes.size(); ++i)
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(a.nodes[i][k], b.nodes[i][k], 1e-15) << "node " << i;
  EXPECT_EQ(a.hexes, b.hexes);
  EXPECT_EQ(a.body, b.body);
  EXPECT_EQ(a.node_sets, b.node_sets);
}

class GmshFormats : public ::testing::TestWithParam<const char*> {};

// gmsh_box.msh (ASCII 4.1) is checked node by node in gmsh_reader_test.cpp; the other
// flavours must give the same mesh: node order, elements and node sets exactly, coordinates
// to the last bit.
TEST_P(GmshFormats, CommittedFileMatchesAscii41) {
  const HexMesh reference = read_gmsh(mesh_data("gmsh_box.msh"), 3);
  const HexMesh mesh = read_gmsh(mesh_data(GetParam()), 3);
  EXPECT_EQ(mesh.hexes.size(), 12u);
  expect_same_mesh(mesh, reference);
}

INSTANTIATE_TEST_SUITE_P(Committed, GmshFormats,
                         ::testing::Values("gmsh_box_msh22.msh", "gmsh_box_msh22_bin.msh", "gmsh_box_msh41_bin.msh"));

#ifdef DIPC_GMSH_EXECUTABLE
// Every flavour as the installed gmsh writes it from gmsh_box.geo.
TEST(GmshFormats, InstalledGmshOutputMatchesCommittedAscii41) {
  const HexMesh reference = read_gmsh(mesh_data("gmsh_box.msh"), 0);
  for (const char* flags : {"-format msh41", "-format msh41 -bin", "-format msh22", "-format msh22 -bin"}) {
    SCOPED_TRACE(flags);
    const std::string out = ::testing::TempDir() + "gmsh_box_generated.msh";
    const std::string command = std::string(DIPC_GMSH_EXECUTABLE) + " -3 " + mesh_data("gmsh_box.geo") + " " + flags +
                                " -o " + out + " > /dev/null 2>&1";
    ASSERT_EQ(std::system(command.c_str()), 0) << command;
    expect_same_mesh(read_gmsh(out, 0), reference);
  }
}
#endif

// Binary MSH 4.1 from a writer whose size_t has 4 bytes (data/make_binary_size4.py).
TEST(GmshFormats, Binary41WithFourByteSizeT) {
  const HexMesh mesh = read_gmsh(mesh_data("binary_size4.msh"), 0);
  ASSERT_EQ(mesh.hexes.size(), 1u);
  EXPECT_EQ(mesh.hexes[0], (Hex{0, 1, 2, 3, 4, 5, 6, 7}));
  EXPECT_EQ(mesh.nodes[6], (Vec3{1, 1, 1}));
  EXPECT_DOUBLE_EQ(test::mesh_volume(mesh), 1.0);
}

// MSH 2 writes an element once per physical group of its entity (under a new tag): one
// hexahedron in two volume groups must stay one element, in both node sets.
TEST(GmshFormats, Msh2ElementInTwoPhysicalGroupsIsOneElement) {
  for (const char* file : {"gmsh_two_groups_msh22.msh", "gmsh_two_groups_msh22_bin.msh"}) {
    SCOPED_TRACE(file);
    const HexMesh mesh = read_gmsh(mesh_data(file), 0);
    ASSERT_EQ(mesh.hexes.size(), 1u);
    EXPECT_EQ(mesh.nodes.size(), 8u);
    const std::vector<std::int64_t> all{0, 1, 2, 3, 4, 5, 6, 7};
    EXPECT_EQ(mesh.node_sets.at("whole"), all);
    EXPECT_EQ(mesh.node_sets.at("also_whole"), all);
    EXPECT_EQ(mesh.node_sets.at("bottom"), (std::vector<std::int64_t>{0, 1, 2, 3}));
    EXPECT_NEAR(test::mesh_volume(mesh), 1.0, 1e-12);
  }
}

// ---- bad files, made from the committed ones ----

std::string file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

template <class T>
std::string bytes_of(T v) {
  std::string s(sizeof v, '\0');
  std::memcpy(s.data(), &v, sizeof v);  // the test host is little-endian, as the files are
  return s;
}

// Offset of the only occurrence of `pattern` at or after `from`.
std::size_t find_once(const std::string& data, const std::string& pattern, std::size_t from = 0) {
  const std::size_t at = data.find(pattern, from);
  EXPECT_NE(at, std::string::npos);
  EXPECT_EQ(data.find(pattern, at + 1), std::string::npos) << "pattern is not unique";
  return at;
}

void expect_rejected(const std::string& name, const std::string& content, const std::string& location,
                     const std::string& fragment) {
  const std::string path = ::testing::TempDir() + name;
  std::ofstream(path, std::ios::binary) << content;
  try {
    read_gmsh(path, 0);
    FAIL() << "accepted " << name;
  } catch (const MeshError& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.rfind(path + location, 0), 0u) << "expected '" << path + location << "' in: " << message;
    EXPECT_NE(message.find(fragment), std::string::npos) << message;
  }
}

TEST(GmshFormatsRejects, BigEndianFiles) {
  for (const char* file : {"gmsh_box_msh41_bin.msh", "gmsh_box_msh22_bin.msh"}) {
    std::string data = file_bytes(mesh_data(file));
    const std::size_t one = find_once(data, std::string(" 1 8\n")) + 5;
    data.replace(one, 4, std::string("\0\0\0\1", 4));
    expect_rejected("big_endian.msh", data, ":2: ", "binary MSH written with big-endian byte order is not supported");
  }
}

TEST(GmshFormatsRejects, UnsupportedDataSize) {
  std::string data = file_bytes(mesh_data("gmsh_box_msh22_bin.msh"));
  data.replace(find_once(data, " 1 8\n"), 5, " 1 4\n");
  expect_rejected("size4.msh", data, ":2: ", "data size 4 is not supported for binary MSH 2.2");
}

// Node 9 is (0.9999999999960252, 0, 0), stored as three doubles in both formats; its x set
// to NaN: the message names the node and the byte of the value.
std::string node_9() { return bytes_of(0.9999999999960252) + bytes_of(0.0) + bytes_of(0.0); }

TEST(GmshFormatsRejects, BinaryNonFiniteCoordinate) {
  for (const char* file : {"gmsh_box_msh41_bin.msh", "gmsh_box_msh22_bin.msh"}) {
    SCOPED_TRACE(file);
    std::string data = file_bytes(mesh_data(file));
    const std::size_t at = find_once(data, node_9());
    data.replace(at, 8, bytes_of(std::numeric_limits<double>::quiet_NaN()));
    expect_rejected("nan_binary.msh", data, ": byte " + std::to_string(at) + ": ",
                    "node 9 has a non-finite x coordinate");
  }
}

// Hexahedron 17 (nodes 1 9 25 14 21 27 35 32) with its first two nodes swapped: check_mesh
// names the element at the byte offset of its tag.
TEST(GmshFormatsRejects, BinaryInvertedElement) {
  struct Case {
    const char* file;
    std::string element;  // tag, then what precedes the node tags
    int node_bytes;
  };
  const std::int64_t nodes[8] = {1, 9, 25, 14, 21, 27, 35, 32};
  std::string nodes64, nodes32;
  for (std::int64_t n : nodes) {
    nodes64 += bytes_of<std::uint64_t>(n);
    nodes32 += bytes_of<std::int32_t>(static_cast<std::int32_t>(n));
  }
  // MSH 4.1: size_t tag then size_t nodes; MSH 2.2: int tag, int physical, int entity, nodes.
  const Case cases[] = {{"gmsh_box_msh41_bin.msh", bytes_of<std::uint64_t>(17), 8},
                        {"gmsh_box_msh22_bin.msh",
                         bytes_of<std::int32_t>(17) + bytes_of<std::int32_t>(1) + bytes_of<std::int32_t>(1), 4}};
  for (const Case& c : cases) {
    SCOPED_TRACE(c.file);
    std::string data = file_bytes(mesh_data(c.file));
    const std::string& node_list = c.node_bytes == 8 ? nodes64 : nodes32;
    const std::size_t at = find_once(data, c.element + node_list);
    const std::size_t first = at + c.element.size();
    std::string swapped = node_list.substr(c.node_bytes, c.node_bytes) + node_list.substr(0, c.node_bytes);
    data.replace(first, 2 * c.node_bytes, swapped);
    expect_rejected("inverted_binary.msh", data, ": byte " + std::to_string(at) + ": ",
                    "element 17 (hexahedron) is inverted");
  }
}

TEST(GmshFormatsRejects, BinaryTruncatedInNodes) {
  for (const char* file : {"gmsh_box_msh41_bin.msh", "gmsh_box_msh22_bin.msh"}) {
    SCOPED_TRACE(file);
    const std::string data = file_bytes(mesh_data(file));
    const std::size_t cut = find_once(data, node_9()) + 3;
    expect_rejected("truncated_binary.msh", data.substr(0, cut), ": byte " + std::to_string(cut - 3) + ": ",
                    "$Nodes section is truncated: the file ends where a node coordinate should be");
  }
}

// ASCII MSH 2.2 errors point at the element's line.
TEST(GmshFormatsRejects, Msh22AsciiElements) {
  const std::string data = file_bytes(mesh_data("gmsh_two_groups_msh22.msh"));
  const std::string second = "3 5 2 2 1 1 2 3 4 5 6 7 8";
  const std::size_t at = find_once(data, second);
  const int line = 1 + static_cast<int>(std::count(data.begin(), data.begin() + at, '\n'));
  auto with = [&](const std::string& element) {
    std::string d = data;
    d.replace(at, second.size(), element);
    return d;
  };
  const std::string where = ":" + std::to_string(line) + ": ";
  expect_rejected("reordered.msh", with("3 5 2 2 1 2 1 3 4 5 6 7 8"), where,
                  "element 3 has the nodes of element 2 in another order");
  expect_rejected("unknown_node.msh", with("3 5 2 2 1 1 2 3 4 5 6 7 99"), where,
                  "element 3 refers to node 99, which is not in $Nodes");
  expect_rejected("tetra.msh", with("3 4 2 2 1 1 2 3 5"), where,
                  "element type 4 (4-node tetrahedron) is not supported");
}

TEST(GmshFormatsRejects, OtherVersions) {
  std::string data = file_bytes(mesh_data("gmsh_box.msh"));
  data.replace(find_once(data, "4.1 0 8"), 7, "4.0 0 8");
  expect_rejected("version_4_0.msh", data, ":2: ", "MSH version 4.0 is not supported (dipc reads 4.1 and 2.2)");
}

}  // namespace
}  // namespace dipc
