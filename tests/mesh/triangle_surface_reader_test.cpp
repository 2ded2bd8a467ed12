// OBJ and STL readers: the committed files in data/surfaces/ (exporter features: v/vt/vn
// corners, negative references, polygons, continuation lines, seams, binary STL whose header
// starts with "solid", multi-solid ASCII STL), and a table of bad inputs written from strings,
// each rejected with a message naming the file and line (ASCII) or facet and byte (binary).
#include "mesh/triangle_surface_reader.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <set>

#include "mesh/mesh_error.hpp"
#include "mesh_test_support.hpp"

namespace dipc {
namespace {

std::string surface_data(const std::string& file) { return test::mesh_data("surfaces/" + file); }

// Enclosed volume by the divergence theorem: V = 1/6 Σ a · (b × c) over the triangles; exact
// for a closed, outward-oriented surface, and it checks orientation as well as connectivity.
double enclosed_volume(const TriangleSurface& s) {
  double v = 0;
  for (const Triangle& t : s.triangles) {
    const Vec3& a = s.vertices[t[0]];
    const Vec3& b = s.vertices[t[1]];
    const Vec3& c = s.vertices[t[2]];
    v += a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) + a[2] * (b[0] * c[1] - b[1] * c[0]);
  }
  return v / 6;
}

// Every undirected edge of a closed 2-manifold is shared by exactly two triangles.
void expect_closed(const TriangleSurface& s) {
  std::multiset<std::pair<std::int64_t, std::int64_t>> edges;
  for (const Triangle& t : s.triangles)
    for (int k = 0; k < 3; ++k) edges.insert({std::min(t[k], t[(k + 1) % 3]), std::max(t[k], t[(k + 1) % 3])});
  for (const auto& e : edges) EXPECT_EQ(edges.count(e), 2u) << e.first << "-" << e.second;
}

TEST(ObjReader, ReadsExporterFeaturesOfACube) {
  const std::string path = surface_data("unit_cube_quads.obj");
  const TriangleSurface s = read_triangle_surface(path);
  EXPECT_EQ(s.source, path);
  EXPECT_FALSE(s.binary);
  EXPECT_EQ(s.vertices.size(), 8u);  // vertex 9 (-0.0) merged into vertex 1
  ASSERT_EQ(s.triangles.size(), 12u);
  const std::vector<std::int64_t> lines{22, 22, 24, 24, 25, 25, 26, 26, 28, 28, 30, 30};
  EXPECT_EQ(s.triangle_origin, lines);
  EXPECT_EQ(describe_triangle(s, 11), path + ":30");
  // Fan triangulation of the first face (9 4 3 2): (9,4,3), (9,3,2), vertex 9 being (0,0,0).
  EXPECT_EQ(s.vertices[s.triangles[0][0]], (Vec3{0, 0, 0}));
  EXPECT_EQ(s.vertices[s.triangles[0][1]], (Vec3{0, 1, 0}));
  EXPECT_EQ(s.vertices[s.triangles[0][2]], (Vec3{1, 1, 0}));
  EXPECT_EQ(s.vertices[s.triangles[1][2]], (Vec3{1, 0, 0}));
  EXPECT_DOUBLE_EQ(enclosed_volume(s), 1.0);
  expect_closed(s);
}

TEST(StlReader, ReadsAsciiWithSeveralSolidsAndUpperCaseKeywords) {
  const std::string path = surface_data("tetrahedron_ascii.stl");
  const TriangleSurface s = read_stl(path);
  EXPECT_EQ(s.vertices.size(), 4u);
  ASSERT_EQ(s.triangles.size(), 4u);
  EXPECT_EQ(s.triangle_origin, (std::vector<std::int64_t>{4, 11, 20, 27}));
  EXPECT_DOUBLE_EQ(enclosed_volume(s), 1.0 / 6);
  expect_closed(s);
}

TEST(StlReader, ReadsBinaryWhoseHeaderStartsWithSolid) {
  const std::string path = surface_data("tetrahedron_binary.stl");
  const TriangleSurface s = read_triangle_surface(path);
  EXPECT_TRUE(s.binary);
  EXPECT_EQ(s.vertices.size(), 4u);
  ASSERT_EQ(s.triangles.size(), 4u);
  EXPECT_EQ(s.triangle_origin, (std::vector<std::int64_t>{0, 1, 2, 3}));
  EXPECT_EQ(describe_triangle(s, 2), path + ": facet 2");
  // The file holds the tetrahedron scaled by 2 and shifted by 0.5.
  EXPECT_EQ(s.vertices[0], (Vec3{0.5, 0.5, 0.5}));
  EXPECT_DOUBLE_EQ(enclosed_volume(s), 8.0 / 6);
  expect_closed(s);
}

TEST(TriangleSurfaceReader, OpenSurfacesAreAllowed) {
  const std::string path = ::testing::TempDir() + "open_square.obj";
  std::ofstream(path) << "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 5 5 5\nf 1 2 3 4\n";
  const TriangleSurface s = read_obj(path);
  EXPECT_EQ(s.triangles.size(), 2u);
  EXPECT_EQ(s.vertices.size(), 4u);  // the unused vertex 5 is dropped
}

// ---- bad inputs ----

struct BadSurface {
  const char* name;      // file name (its extension picks the reader)
  const char* content;   // file text; binary STL cases are built in binary_case()
  const char* location;  // what must follow the path: ":<line>: " or ": facet ..."
  const char* fragment;
};

std::ostream& operator<<(std::ostream& os, const BadSurface& b) { return os << b.name; }

class TriangleSurfaceRejects : public ::testing::TestWithParam<BadSurface> {};

TEST_P(TriangleSurfaceRejects, WithLocatedMessage) {
  const BadSurface& bad = GetParam();
  const std::string path = ::testing::TempDir() + bad.name;
  if (bad.content) std::ofstream(path, std::ios::binary) << bad.content;
  try {
    read_triangle_surface(path);
    FAIL() << "accepted " << bad.name;
  } catch (const MeshError& e) {
    const std::string message = e.what();
    const std::string prefix = path + bad.location;
    EXPECT_EQ(message.rfind(prefix, 0), 0u) << "expected prefix '" << prefix << "' in: " << message;
    EXPECT_NE(message.find(bad.fragment), std::string::npos) << message;
  }
}

INSTANTIATE_TEST_SUITE_P(
    BadFiles, TriangleSurfaceRejects,
    ::testing::Values(
        BadSurface{"nan.obj", "v 0 0 0\nv 1 nan 0\nv 0 1 0\nf 1 2 3\n",
                   ":2: ", "vertex 2 has a non-finite y coordinate"},
        BadSurface{"inf.obj", "v 0 0 0\nv 1 0 0\nv 0 1 -inf\nf 1 2 3\n", ":3: ", "non-finite z coordinate"},
        BadSurface{"two_numbers.obj", "v 0 0\n", ":1: ", "vertex needs 3 coordinates"},
        BadSurface{"word.obj", "v 0 zero 0\n", ":1: ", "vertex y coordinate is not a number"},
        BadSurface{"weight.obj", "v 0 0 0 2\n", ":1: ", "vertex weight w must be 1"},
        BadSurface{"index_zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n",
                   ":4: ", "refers to vertex 0 (OBJ counts from 1)"},
        BadSurface{"index_past_end.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n\nf 1 2 4\n",
                   ":5: ", "face refers to vertex 4 but the file has 3 vertices"},
        BadSurface{"negative_past_start.obj", "v 0 0 0\nv 1 0 0\nf -1 -2 -3\nv 0 1 0\n",
                   ":3: ", "refers to vertex -3 but only 2 vertices precede it"},
        BadSurface{"two_corners.obj", "v 0 0 0\nv 1 0 0\nf 1 2\n", ":3: ", "face needs at least 3 corners, found 2"},
        BadSurface{"four_slashes.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/1/1/1 2 3\n", ":4: ", "has more than v/vt/vn"},
        BadSurface{"bad_corner.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 x3\n",
                   ":4: ", "face corner 'x3' is not v, v/vt, v//vn or v/vt/vn"},
        BadSurface{"empty_vertex.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 /3\n", ":4: ", "face corner '/3' is not v"},
        BadSurface{"collinear.obj", "v 0 0 0\nv 1 1 1\nv 2 2 2\n# c\nf 1 2 3\n",
                   ":5: ", "(2 2 2): area 0, its corners are collinear"},
        BadSurface{"repeated_corner.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 1\n", ":5: ",
                   "degenerate triangle with corners (0 0 0), (1 0 0), (0 0 0): two of its corners "
                   "are the same point"},
        // Two vertex statements at one point are merged, so the face uses one point twice.
        BadSurface{"coincident.obj", "v 0 0 0\nv 1 0 0\nv 1 0 0\nf 1 2 3\n",
                   ":4: ", "two of its corners are the same point"},
        BadSurface{"no_faces.obj", "v 0 0 0\n", ": ", "no faces ('f' statements)"},
        BadSurface{"line_element.obj", "v 0 0 0\nv 1 0 0\nl 1 2\n", ":3: ", "line elements are not supported"},
        BadSurface{"freeform.obj", "cstype bspline\n", ":1: ", "free-form geometry ('cstype') is not supported"},
        BadSurface{"unknown.obj", "v 0 0 0\nvertex 1 2 3\n", ":2: ", "unknown OBJ statement 'vertex'"},
        BadSurface{"missing.obj", nullptr, ": ", "cannot open file"},
        BadSurface{"mesh.ply", "ply\n", ": ", "unknown surface file extension 'ply'"},
        BadSurface{"truncated.stl", "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n",
                   ":5: ", "ASCII STL is truncated: the file ends where 'vertex' should be"},
        BadSurface{"quad.stl",
                   "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n"
                   "vertex 1 1 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid\n",
                   ":7: ", "facet has more than 3 vertices"},
        BadSurface{"nan.stl",
                   "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 NaN\n"
                   "vertex 1 1 0\nendloop\nendfacet\nendsolid\n",
                   ":5: ", "non-finite vertex z coordinate"},
        BadSurface{"misspelt.stl", "solid t\nfacet normal 0 0 1\nouter lop\n", ":3: ", "expected 'loop', found 'lop'"},
        BadSurface{"degenerate.stl",
                   "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n"
                   "vertex 2 0 0\nendloop\nendfacet\nendsolid\n",
                   ":4: ", "degenerate triangle"},
        BadSurface{"not_stl.stl", "hello\n", ": ", "not an STL file"}),
    [](const ::testing::TestParamInfo<BadSurface>& info) {
      std::string n = info.param.name;
      for (char& c : n)
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
      return n;
    });

// A binary STL of `facets` facets, each a valid triangle, with hooks to break one.
std::string binary_stl(std::uint32_t facets) {
  std::string out(80, ' ');
  for (int b = 0; b < 4; ++b) out.push_back(static_cast<char>((facets >> (8 * b)) & 0xff));
  for (std::uint32_t f = 0; f < facets; ++f) {
    const float v[12] = {0, 0, 1, float(f), 0, 0, float(f) + 1, 0, 0, float(f), 1, 0};
    for (float x : v) {
      std::uint32_t bits;
      std::memcpy(&bits, &x, 4);
      for (int b = 0; b < 4; ++b) out.push_back(static_cast<char>((bits >> (8 * b)) & 0xff));
    }
    out += std::string(2, '\0');
  }
  return out;
}

void set_float(std::string& stl, std::size_t offset, float x) {
  std::uint32_t bits;
  std::memcpy(&bits, &x, 4);
  for (int b = 0; b < 4; ++b) stl[offset + b] = static_cast<char>((bits >> (8 * b)) & 0xff);
}

void expect_binary_rejected(const std::string& name, const std::string& content, const std::string& location,
                            const std::string& fragment) {
  const std::string path = ::testing::TempDir() + name;
  std::ofstream(path, std::ios::binary) << content;
  try {
    read_stl(path);
    FAIL() << "accepted " << name;
  } catch (const MeshError& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.rfind(path + location, 0), 0u) << message;
    EXPECT_NE(message.find(fragment), std::string::npos) << message;
  }
}

TEST(StlReader, BinaryGoodFileReads) {
  const std::string path = ::testing::TempDir() + "three.stl";
  std::ofstream(path, std::ios::binary) << binary_stl(3);
  const TriangleSurface s = read_stl(path);
  EXPECT_EQ(s.triangles.size(), 3u);
  EXPECT_EQ(s.vertices.size(), 7u);  // neighbours share (1,0,0) and (2,0,0)
}

TEST(StlReader, BinaryRejectsNonFiniteWithFacetAndByte) {
  std::string stl = binary_stl(3);
  // facet 2, corner 1, y: 84 + 50*2 + 12 (normal) + 12 (corner 0) + 4
  set_float(stl, 84 + 100 + 12 + 12 + 4, std::nanf(""));
  expect_binary_rejected("nan_binary.stl", stl, ": facet 2 (byte 184): ", "corner 1 has a non-finite y coordinate");
}

TEST(StlReader, BinaryRejectsDegenerateWithFacetAndByte) {
  std::string stl = binary_stl(3);
  // facet 1's third corner onto the line of its first two: (1,0,0), (2,0,0), (1.5,0,0);
  // corner 2 starts after the normal and two corners: 84 + 50 + 12 + 24
  set_float(stl, 84 + 50 + 12 + 24, 1.5f);
  set_float(stl, 84 + 50 + 12 + 24 + 4, 0.0f);
  expect_binary_rejected("degenerate_binary.stl", stl, ": facet 1 (byte 134): ", "degenerate triangle");
}

TEST(StlReader, BinaryRejectsSizeMismatchAndEmpty) {
  std::string stl = binary_stl(3);
  stl.pop_back();
  expect_binary_rejected("short_binary.stl", stl, ": ",
                         "binary STL with 3 facets (byte 80) must be 234 bytes, the file has 233");
  expect_binary_rejected("empty_binary.stl", binary_stl(0), ": ", "binary STL with no facets");
}

}  // namespace
}  // namespace dipc
