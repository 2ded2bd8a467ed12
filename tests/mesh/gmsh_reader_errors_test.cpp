// Table of bad MSH files (tests/mesh/data): each must be rejected with a MeshError whose
// message starts with "<path>:<line>: " and says what is wrong.
#include <gtest/gtest.h>

#include "mesh/gmsh_reader.hpp"
#include "mesh/mesh_error.hpp"
#include "mesh_test_support.hpp"

namespace dipc {
namespace {

struct BadFile {
  const char* file;
  int line;              // line the message must point at (0: no line, e.g. file not found)
  const char* fragment;  // distinctive part of the message
};

std::ostream& operator<<(std::ostream& os, const BadFile& f) { return os << f.file; }

class GmshReaderRejects : public ::testing::TestWithParam<BadFile> {};

TEST_P(GmshReaderRejects, WithLocatedMessage) {
  const BadFile& bad = GetParam();
  const std::string path = test::mesh_data(bad.file);
  try {
    read_gmsh(path, 0);
    FAIL() << "read_gmsh accepted " << bad.file;
  } catch (const MeshError& e) {
    const std::string message = e.what();
    const std::string prefix = bad.line > 0 ? path + ":" + std::to_string(bad.line) + ": " : path + ": ";
    EXPECT_EQ(message.rfind(prefix, 0), 0u) << "expected prefix '" << prefix << "' in: " << message;
    EXPECT_NE(message.find(bad.fragment), std::string::npos) << message;
  }
}

INSTANTIATE_TEST_SUITE_P(
    BadFiles, GmshReaderRejects,
    ::testing::Values(BadFile{"truncated_nodes.msh", 19, "$Nodes section is truncated: the file ends"},
                      BadFile{"coordinates_missing.msh", 22, "$Nodes section is truncated: found '$EndNodes'"},
                      BadFile{"inverted.msh", 27, "element 17 (hexahedron) is inverted: det J = -0.125 at corner 0"},
                      BadFile{"degenerate.msh", 27, "element 17 (hexahedron) is degenerate: det J = 0"},
                      BadFile{"nan_coordinate.msh", 20, "node 6 has a non-finite y coordinate"},
                      BadFile{"unused_node.msh", 15, "node 9 is not used by any element"},
                      BadFile{"unknown_node_tag.msh", 27, "element 17 refers to node 99, which is not in $Nodes"},
                      // What Gmsh writes when only a surface is in a physical group: no volume elements.
                      BadFile{"no_hexahedra.msh", 54, "no hexahedra (element type 5)"},
                      BadFile{"duplicate_node_tag.msh", 13, "node 2 is defined twice"},
                      BadFile{"tetrahedron.msh", 20,
                              "4-node tetrahedron) is not supported: dipc needs an all-hexahedral mesh"},
                      BadFile{"hexahedron_27.msh", 64,
                              "27-node second-order hexahedron) is not supported: dipc reads linear hexahedra only"},
                      BadFile{"malformed_elements.msh", 27,
                              "$Elements section is malformed: expected an element node tag, found 'four'"},
                      BadFile{"partitioned.msh", 4, "partitioned meshes are not supported"},
                      BadFile{"ambiguous_groups.msh", 6, "would both be node set 'physical_1'"},
                      BadFile{"does_not_exist.msh", 0, "cannot open the file"},
                      // A $MeshFormat header that does not match the body (issue 32, item 8): the
                      // message names the version the header declares.
                      BadFile{"version_22_header_41_body.msh", 23, "MSH 2.2, the version its $MeshFormat declares"},
                      BadFile{"version_41_header_22_body.msh", 14, "MSH 4.1, the version its $MeshFormat declares"}));

TEST(GmshReader, RejectsNegativeBodyId) {
  const std::string path = test::mesh_data("block_2x1x1.msh");
  try {
    read_gmsh(path, -2);
    FAIL() << "negative body id accepted";
  } catch (const MeshError& e) {
    EXPECT_NE(std::string(e.what()).find(path + ": body id -2 is negative"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace dipc
