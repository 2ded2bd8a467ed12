// Tests of hex_face_nodes and extract_boundary_faces: the face table on the reference cube,
// face counts, outward orientation and total area on boxes (also distorted and renumbered),
// two bodies, glued bodies, an internal cavity, and the errors.
#include "mesh/boundary_faces.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <random>
#include <set>
#include <string>

#include "mesh/box_generator.hpp"
#include "mesh/hex8_reference.hpp"
#include "mesh/mesh_checks.hpp"
#include "mesh/mesh_error.hpp"
#include "surface_test_support.hpp"

namespace dipc {
namespace {

using test::dot;
using test::norm;
using Quad = std::array<std::int64_t, 4>;

Quad face_node_ids(const HexMesh& mesh, const BoundaryFace& face) {
  const std::array<int, 4> local = hex_face_nodes(face.face);
  Quad q;
  for (int i = 0; i < 4; ++i) q[i] = mesh.hexes[face.element][local[i]];
  return q;
}

Vec3 reference_corner(int a) { return {hex8::corner_xi(a), hex8::corner_eta(a), hex8::corner_zeta(a)}; }

TEST(HexFaceNodes, FacesLieOnTheirPlanesAndTurnCounterClockwiseSeenFromOutside) {
  std::array<int, 8> faces_per_node{};
  for (int f = 0; f < kHexFaces; ++f) {
    const std::array<int, 4> nodes = hex_face_nodes(f);
    const int axis = f / 2;
    const double side = f % 2 ? 1.0 : -1.0;
    Vec3 outward{0, 0, 0};
    outward[axis] = side;
    for (int i = 0; i < 4; ++i) {
      ++faces_per_node[nodes[i]];
      EXPECT_EQ(reference_corner(nodes[i])[axis], side) << "face " << f << " node " << nodes[i];
      // At every corner the turn from the next corner to the previous one is a right-hand
      // rotation about the outward normal: the polygon is convex and counter-clockwise.
      const Vec3 x = reference_corner(nodes[i]);
      const Vec3 next = reference_corner(nodes[(i + 1) % 4]);
      const Vec3 prev = reference_corner(nodes[(i + 3) % 4]);
      const Vec3 n = test::cross(test::sub(next, x), test::sub(prev, x));
      EXPECT_EQ(n[axis], 4.0 * side) << "face " << f << " corner " << i;
      EXPECT_EQ(dot(n, n), 16.0) << "face " << f << " corner " << i;
      EXPECT_GT(dot(n, outward), 0.0);
    }
  }
  for (int a = 0; a < 8; ++a) EXPECT_EQ(faces_per_node[a], 3) << "node " << a;
  EXPECT_THROW(hex_face_nodes(-1), MeshError);
  EXPECT_THROW(hex_face_nodes(6), MeshError);
}

// Checks that `faces` is the boundary of the axis-aligned box [lo, hi] meshed by `mesh`:
// each face lies on a side of the box, its area vector points out of the box, and the areas
// add up to the box's surface area.
void expect_box_boundary(const HexMesh& mesh, const std::vector<BoundaryFace>& faces, const Vec3& lo, const Vec3& hi) {
  double area = 0;
  for (const BoundaryFace& face : faces) {
    const Quad q = face_node_ids(mesh, face);
    const Vec3 a = test::quad_area_vector(mesh, q);
    const Vec3 c = test::centroid(mesh, q.data(), 4);
    area += norm(a);
    int axis = 0;
    for (int d = 1; d < 3; ++d) {
      if (std::abs(a[d]) > std::abs(a[axis])) axis = d;
    }
    EXPECT_NEAR(std::abs(a[axis]), norm(a), 1e-12 * norm(a)) << "not axis-aligned";
    const double plane = a[axis] > 0 ? hi[axis] : lo[axis];
    EXPECT_NEAR(c[axis], plane, 1e-12) << "element " << face.element << " face " << face.face
                                       << " is not on the side its normal points out of";
  }
  const Vec3 s = test::sub(hi, lo);
  EXPECT_NEAR(area, 2 * (s[0] * s[1] + s[1] * s[2] + s[0] * s[2]), 1e-12);
}

TEST(ExtractBoundaryFaces, BoxCountOrientationAndArea) {
  const int nx = 3, ny = 4, nz = 5;
  const HexMesh mesh = generate_box({2, 1, 0.5}, {nx, ny, nz}, {-1, 2, 0.5}, 0, "box");
  const std::vector<BoundaryFace> faces = extract_boundary_faces(mesh);
  EXPECT_EQ(faces.size(), static_cast<std::size_t>(2 * (nx * ny + ny * nz + nx * nz)));
  expect_box_boundary(mesh, faces, {-1, 2, 0.5}, {1, 3, 1});
  // Sorted by (element, face), no face twice.
  for (std::size_t i = 1; i < faces.size(); ++i) {
    EXPECT_TRUE(faces[i - 1].element < faces[i].element ||
                (faces[i - 1].element == faces[i].element && faces[i - 1].face < faces[i].face));
  }
}

TEST(ExtractBoundaryFaces, SingleElementHasAllSixFaces) {
  const HexMesh mesh = generate_box({1, 1, 1}, {1, 1, 1}, {0, 0, 0}, 0, "cube");
  const std::vector<BoundaryFace> faces = extract_boundary_faces(mesh);
  ASSERT_EQ(faces.size(), 6u);
  for (int f = 0; f < 6; ++f) {
    EXPECT_EQ(faces[f].element, 0);
    EXPECT_EQ(faces[f].face, f);
  }
}

TEST(ExtractBoundaryFaces, DistortedAndRenumberedMeshKeepsItsBoundary) {
  // Interior nodes moved (boundary unchanged), then node ids and element order permuted:
  // the same faces must be found, each pointing away from its own element's centroid.
  HexMesh mesh = generate_box({4, 3, 2}, {4, 3, 2}, {0, 0, 0}, 0, "box");
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> jitter(-0.2, 0.2);
  for (Vec3& x : mesh.nodes) {
    const bool interior = x[0] > 0 && x[0] < 4 && x[1] > 0 && x[1] < 3 && x[2] > 0 && x[2] < 2;
    if (interior)
      for (double& c : x) c += jitter(rng);
  }
  std::vector<std::int64_t> new_id(mesh.num_nodes());
  std::iota(new_id.begin(), new_id.end(), 0);
  std::shuffle(new_id.begin(), new_id.end(), rng);
  HexMesh renumbered;
  renumbered.nodes.resize(mesh.num_nodes());
  for (std::size_t n = 0; n < mesh.num_nodes(); ++n) renumbered.nodes[new_id[n]] = mesh.nodes[n];
  std::vector<std::size_t> element_order(mesh.num_elements());
  std::iota(element_order.begin(), element_order.end(), 0);
  std::shuffle(element_order.begin(), element_order.end(), rng);
  for (std::size_t e : element_order) {
    Hex h = mesh.hexes[e];
    for (auto& n : h) n = new_id[n];
    renumbered.hexes.push_back(h);
    renumbered.body.push_back(0);
  }
  ASSERT_NO_THROW(check_mesh(renumbered, "distorted box"));

  const std::vector<BoundaryFace> faces = extract_boundary_faces(renumbered);
  expect_box_boundary(renumbered, faces, {0, 0, 0}, {4, 3, 2});
  std::set<std::set<std::int64_t>> found, expected;
  for (const BoundaryFace& face : faces) {
    const Quad q = face_node_ids(renumbered, face);
    found.insert(std::set<std::int64_t>(q.begin(), q.end()));
    std::array<std::int64_t, 8> all;
    std::copy(renumbered.hexes[face.element].begin(), renumbered.hexes[face.element].end(), all.begin());
    const Vec3 out = test::sub(test::centroid(renumbered, q.data(), 4), test::centroid(renumbered, all.data(), 8));
    EXPECT_GT(dot(test::quad_area_vector(renumbered, q), out), 0.0);
  }
  for (const BoundaryFace& face : extract_boundary_faces(mesh)) {
    std::set<std::int64_t> ids;
    for (std::int64_t n : face_node_ids(mesh, face)) ids.insert(new_id[n]);
    expected.insert(ids);
  }
  EXPECT_EQ(found, expected);
}

TEST(ExtractBoundaryFaces, TwoBodiesEachKeepTheirWholeBoundary) {
  HexMesh mesh = generate_box({2, 1, 1}, {2, 1, 1}, {0, 0, 0}, 0, "lower");
  mesh.append(generate_box({1, 1, 1}, {2, 2, 2}, {0, 0, 1}, 1, "upper"));
  const std::vector<BoundaryFace> faces = extract_boundary_faces(mesh);
  // The upper box touches the lower one geometrically but shares no nodes: no face is glued.
  ASSERT_EQ(faces.size(), 10u + 24u);
  std::vector<BoundaryFace> lower, upper;
  for (const BoundaryFace& f : faces) (mesh.body[f.element] == 0 ? lower : upper).push_back(f);
  EXPECT_EQ(lower.size(), 10u);
  expect_box_boundary(mesh, lower, {0, 0, 0}, {2, 1, 1});
  expect_box_boundary(mesh, upper, {0, 0, 1}, {1, 1, 2});
}

TEST(ExtractBoundaryFaces, BodiesSharingNodesAreGlued) {
  HexMesh mesh = generate_box({2, 1, 1}, {2, 1, 1}, {0, 0, 0}, 0, "bar");
  mesh.body = {0, 1};
  EXPECT_EQ(extract_boundary_faces(mesh).size(), 10u);
}

TEST(ExtractBoundaryFaces, CavityFacesPointIntoTheCavity) {
  const HexMesh mesh = test::box_with_cavity(3);
  const std::vector<BoundaryFace> faces = extract_boundary_faces(mesh);
  ASSERT_EQ(faces.size(), 54u + 6u);
  const Vec3 cavity_centre{1.5, 1.5, 1.5};
  std::vector<BoundaryFace> outer;
  int inner = 0;
  double inner_area = 0;
  for (const BoundaryFace& face : faces) {
    const Quad q = face_node_ids(mesh, face);
    const Vec3 c = test::centroid(mesh, q.data(), 4);
    if (norm(test::sub(c, cavity_centre)) < 0.6) {
      ++inner;
      const Vec3 a = test::quad_area_vector(mesh, q);
      inner_area += norm(a);
      // Outward from the solid is into the cavity.
      EXPECT_GT(dot(a, test::sub(cavity_centre, c)), 0.0);
    } else {
      outer.push_back(face);
    }
  }
  EXPECT_EQ(inner, 6);
  EXPECT_NEAR(inner_area, 6.0, 1e-12);
  expect_box_boundary(mesh, outer, {0, 0, 0}, {3, 3, 3});
}

void expect_mesh_error(const HexMesh& mesh, const std::string& fragment) {
  try {
    extract_boundary_faces(mesh);
    ADD_FAILURE() << "no MeshError; expected one mentioning '" << fragment << "'";
  } catch (const MeshError& e) {
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

TEST(ExtractBoundaryFaces, RejectsBadNodeIdsAndFacesOfThreeElements) {
  HexMesh bad_id = generate_box({2, 1, 1}, {2, 1, 1}, {0, 0, 0}, 0, "bar");
  bad_id.hexes[1][6] = 12;
  expect_mesh_error(bad_id, "element 1 node 6 has id 12, outside [0, 12)");

  HexMesh three = generate_box({2, 1, 1}, {2, 1, 1}, {0, 0, 0}, 0, "bar");
  three.hexes.push_back(three.hexes[1]);
  three.body.push_back(0);
  expect_mesh_error(three, "3 elements share one face (element 0 face 1, element 1 face 0, "
                           "element 2 face 0)");
}

}  // namespace
}  // namespace dipc
