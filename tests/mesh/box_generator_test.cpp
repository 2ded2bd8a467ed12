// Tests of generate_box: counts, numbering, orientation, face node sets, volume, errors.
#include "mesh/box_generator.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "mesh/hex8_reference.hpp"
#include "mesh/mesh_checks.hpp"
#include "mesh/mesh_error.hpp"
#include "mesh_test_support.hpp"

namespace dipc {
namespace {

const std::array<double, 3> kSize{2.0, 0.5, 1.5};
const std::array<int, 3> kResolution{4, 2, 3};
const std::array<double, 3> kOrigin{-1.0, 0.25, 3.0};

TEST(BoxGenerator, CountsAndBodyIds) {
  const HexMesh mesh = generate_box(kSize, kResolution, kOrigin, 2, "beam");
  EXPECT_EQ(mesh.num_nodes(), 5u * 3u * 4u);
  EXPECT_EQ(mesh.num_elements(), 4u * 2u * 3u);
  ASSERT_EQ(mesh.body.size(), mesh.num_elements());
  for (int b : mesh.body) EXPECT_EQ(b, 2);
}

TEST(BoxGenerator, DocumentedNumbering) {
  const HexMesh mesh = generate_box(kSize, kResolution, kOrigin, 0, "beam");
  // Node (i, j, k) = (1, 2, 3) has id 1 + 5 * (2 + 3 * 3) and sits at origin + (i, j, k) h.
  const Vec3& x = mesh.nodes[1 + 5 * (2 + 3 * 3)];
  EXPECT_DOUBLE_EQ(x[0], -1.0 + 0.5);
  EXPECT_DOUBLE_EQ(x[1], 0.25 + 0.5);
  EXPECT_DOUBLE_EQ(x[2], 3.0 + 1.5);
  // Element (i, j, k) = (3, 1, 2) has id 3 + 4 * (1 + 2 * 2); its node 0 is node (3, 1, 2)
  // and its node 6 the opposite corner (4, 2, 3).
  const Hex& h = mesh.hexes[3 + 4 * (1 + 2 * 2)];
  EXPECT_EQ(h[0], 3 + 5 * (1 + 3 * 2));
  EXPECT_EQ(h[6], 4 + 5 * (2 + 3 * 3));
}

TEST(BoxGenerator, GmshCornerOrderingAndPositiveJacobian) {
  const HexMesh mesh = generate_box(kSize, kResolution, kOrigin, 0, "beam");
  const double h[3] = {0.5, 0.25, 0.5};
  for (std::size_t e = 0; e < mesh.num_elements(); ++e) {
    double X[24];
    test::element_coordinates(mesh, e, X);
    // Each corner sits at node 0 + (1 ± ξ_a, 1 ± η_a, 1 ± ζ_a) h / 2, as in hex_mesh.hpp.
    for (int a = 0; a < 8; ++a) {
      EXPECT_DOUBLE_EQ(X[3 * a + 0] - X[0], 0.5 * (1 + hex8::corner_xi(a)) * h[0]);
      EXPECT_DOUBLE_EQ(X[3 * a + 1] - X[1], 0.5 * (1 + hex8::corner_eta(a)) * h[1]);
      EXPECT_DOUBLE_EQ(X[3 * a + 2] - X[2], 0.5 * (1 + hex8::corner_zeta(a)) * h[2]);
    }
    // An axis-aligned brick maps with J = diag(h/2) everywhere.
    EXPECT_NEAR(hex8::min_jacobian_determinant(X), h[0] * h[1] * h[2] / 8, 1e-15);
  }
}

TEST(BoxGenerator, TotalVolume) {
  const HexMesh mesh = generate_box(kSize, kResolution, kOrigin, 0, "beam");
  EXPECT_NEAR(test::mesh_volume(mesh), 2.0 * 0.5 * 1.5, 1e-13);
}

TEST(BoxGenerator, FaceNodeSetsHoldExactlyTheNodesOnEachFace) {
  const HexMesh mesh = generate_box(kSize, kResolution, kOrigin, 0, "beam");
  ASSERT_EQ(mesh.node_sets.size(), 7u);
  const auto& all = mesh.node_sets.at("beam");
  ASSERT_EQ(all.size(), mesh.num_nodes());
  for (std::size_t n = 0; n < all.size(); ++n) EXPECT_EQ(all[n], static_cast<std::int64_t>(n));

  const char* faces[6] = {"beam.xmin", "beam.xmax", "beam.ymin", "beam.ymax", "beam.zmin", "beam.zmax"};
  for (int f = 0; f < 6; ++f) {
    const int axis = f / 2;
    const double plane = kOrigin[axis] + (f % 2 ? kSize[axis] : 0.0);
    std::vector<std::int64_t> expected;
    for (std::size_t n = 0; n < mesh.num_nodes(); ++n)
      if (mesh.nodes[n][axis] == plane) expected.push_back(static_cast<std::int64_t>(n));
    const int a = (axis + 1) % 3, b = (axis + 2) % 3;
    EXPECT_EQ(expected.size(), static_cast<std::size_t>((kResolution[a] + 1) * (kResolution[b] + 1))) << faces[f];
    EXPECT_EQ(mesh.node_sets.at(faces[f]), expected) << faces[f];
  }
}

TEST(BoxGenerator, PassesMeshChecks) {
  const HexMesh mesh = generate_box({1, 1, 1}, {1, 1, 1}, {0, 0, 0}, 0, "cube");
  EXPECT_NO_THROW(check_mesh(mesh, "generated"));
  EXPECT_DOUBLE_EQ(bounding_box_diagonal(mesh), std::sqrt(3.0));
}

void expect_box_error(const std::array<double, 3>& size, const std::array<int, 3>& resolution,
                      const std::array<double, 3>& origin, int body, const std::string& name,
                      const std::string& fragment) {
  try {
    generate_box(size, resolution, origin, body, name);
    ADD_FAILURE() << "no MeshError; expected one mentioning '" << fragment << "'";
  } catch (const MeshError& e) {
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

TEST(BoxGenerator, RejectsInvalidParameters) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  expect_box_error({1, 1, 1}, {1, 0, 1}, {0, 0, 0}, 0, "b", "resolution along y is 0");
  expect_box_error({1, 1, 1}, {-2, 1, 1}, {0, 0, 0}, 0, "b", "resolution along x is -2");
  expect_box_error({1, 1, 0}, {1, 1, 1}, {0, 0, 0}, 0, "b", "size along z");
  expect_box_error({1, -1, 1}, {1, 1, 1}, {0, 0, 0}, 0, "b", "size along y");
  expect_box_error({nan, 1, 1}, {1, 1, 1}, {0, 0, 0}, 0, "b", "size along x");
  expect_box_error({1, inf, 1}, {1, 1, 1}, {0, 0, 0}, 0, "b", "size along y");
  expect_box_error({1, 1, 1}, {1, 1, 1}, {0, nan, 0}, 0, "b", "origin along y");
  expect_box_error({1, 1, 1}, {1, 1, 1}, {0, 0, 0}, -1, "b", "body id -1");
  expect_box_error({1, 1, 1}, {1, 1, 1}, {0, 0, 0}, 0, "", "needs a name");
  expect_box_error({1, 1, 1}, {2000000000, 2000000000, 2000000000}, {0, 0, 0}, 0, "b", "too large");
}

}  // namespace
}  // namespace dipc
