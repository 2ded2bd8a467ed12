// Tests of build_surface_mesh: the quad split rule, outward triangles and their total area,
// closed consistently oriented surfaces (every edge in two triangles, once in each
// direction), Euler characteristics of a box, two bodies and a cavity, edge and vertex
// tables, and the body rule for primitives shared by glued bodies.
#include "mesh/surface_mesh.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <set>
#include <utility>

#include "mesh/box_generator.hpp"
#include "mesh/mesh_error.hpp"
#include "surface_test_support.hpp"

namespace dipc {
namespace {

using test::dot;
using test::norm;

TEST(QuadSplit, DiagonalThroughTheSmallestIdKeepsTheOrientation) {
  const std::int64_t ids[4][4] = {{5, 9, 7, 8}, {9, 3, 7, 8}, {9, 7, 2, 8}, {9, 7, 8, 1}};
  for (int m = 0; m < 4; ++m) {
    EXPECT_EQ(quad_split_corner(ids[m]), m);
    const std::array<int, 3> t0 = quad_triangle_corners(m, 0);
    const std::array<int, 3> t1 = quad_triangle_corners(m, 1);
    // Both triangles start at the split corner, share the diagonal (m, m+2), and together
    // cover the 4 corners with the quad's cyclic order.
    EXPECT_EQ(t0, (std::array<int, 3>{m, (m + 1) % 4, (m + 2) % 4}));
    EXPECT_EQ(t1, (std::array<int, 3>{m, (m + 2) % 4, (m + 3) % 4}));
  }
}

// Checks the invariants every SurfaceMesh must satisfy and returns V - E + F.
std::int64_t expect_valid_closed_surface(const HexMesh& mesh, const SurfaceMesh& s) {
  EXPECT_EQ(s.triangles.size(), 2 * s.quads.size());
  EXPECT_EQ(s.triangle_body.size(), s.triangles.size());
  EXPECT_EQ(s.triangle_edges.size(), s.triangles.size());
  EXPECT_EQ(s.edge_body.size(), s.edges.size());
  EXPECT_EQ(s.vertex_body.size(), s.vertices.size());
  EXPECT_TRUE(std::is_sorted(s.edges.begin(), s.edges.end()));
  EXPECT_TRUE(std::adjacent_find(s.edges.begin(), s.edges.end()) == s.edges.end());
  EXPECT_TRUE(std::is_sorted(s.vertices.begin(), s.vertices.end()));
  EXPECT_TRUE(std::adjacent_find(s.vertices.begin(), s.vertices.end()) == s.vertices.end());

  std::map<std::pair<std::int64_t, std::int64_t>, int> directed;
  std::set<std::int64_t> corners;
  for (std::size_t t = 0; t < s.triangles.size(); ++t) {
    const auto& tri = s.triangles[t];
    const BoundaryFace& quad = s.quads[t / 2];
    EXPECT_EQ(s.triangle_body[t], mesh.body[quad.element]);
    // Corners come from the quad, and the split diagonal starts at its smallest node id.
    const std::array<int, 4> local = hex_face_nodes(quad.face);
    std::int64_t q[4];
    for (int i = 0; i < 4; ++i) q[i] = mesh.hexes[quad.element][local[i]];
    EXPECT_EQ(tri[0], *std::min_element(q, q + 4)) << "triangle " << t;
    for (std::int64_t node : tri) EXPECT_NE(std::find(q, q + 4, node), q + 4);
    for (int i = 0; i < 3; ++i) {
      const std::int64_t u = tri[i], v = tri[(i + 1) % 3];
      ++directed[{u, v}];
      corners.insert(u);
      const std::int64_t e = s.triangle_edges[t][i];
      EXPECT_EQ(s.edges.at(e), (std::array<std::int64_t, 2>{std::min(u, v), std::max(u, v)}));
    }
  }
  // Closed and consistently oriented: each directed side once, and its reverse once.
  for (const auto& [side, count] : directed) {
    EXPECT_EQ(count, 1) << side.first << "->" << side.second;
    EXPECT_EQ(directed.count({side.second, side.first}), 1u) << side.first << "-" << side.second;
  }
  EXPECT_EQ(directed.size(), 2 * s.edges.size());
  EXPECT_EQ(std::vector<std::int64_t>(corners.begin(), corners.end()), s.vertices);
  return static_cast<std::int64_t>(s.vertices.size()) - static_cast<std::int64_t>(s.edges.size()) +
         static_cast<std::int64_t>(s.triangles.size());
}

// Sum of triangle areas, and every triangle's normal must point out of the box [lo, hi]:
// along +axis when its centroid is on the hi side, -axis on the lo side.
double box_triangle_area(const HexMesh& mesh, const SurfaceMesh& s, const Vec3& lo, const Vec3& hi) {
  double area = 0;
  for (std::size_t t = 0; t < s.triangles.size(); ++t) {
    const auto& tri = s.triangles[t];
    const Vec3 a = test::triangle_area_vector(mesh.nodes[tri[0]], mesh.nodes[tri[1]], mesh.nodes[tri[2]]);
    const Vec3 c = test::centroid(mesh, tri.data(), 3);
    area += norm(a);
    int axis = 0;
    for (int d = 1; d < 3; ++d) {
      if (std::abs(a[d]) > std::abs(a[axis])) axis = d;
    }
    EXPECT_NEAR(c[axis], a[axis] > 0 ? hi[axis] : lo[axis], 1e-12) << "triangle " << t;
  }
  return area;
}

TEST(SurfaceMesh, BoxIsAClosedOutwardSphere) {
  const int nx = 4, ny = 2, nz = 3;
  const HexMesh mesh = generate_box({2, 1, 3}, {nx, ny, nz}, {1, 0, -1}, 3, "box");
  const SurfaceMesh s = build_surface_mesh(mesh);
  EXPECT_EQ(s.quads.size(), static_cast<std::size_t>(2 * (nx * ny + ny * nz + nx * nz)));
  EXPECT_EQ(expect_valid_closed_surface(mesh, s), 2);
  const std::size_t all_nodes = (nx + 1) * (ny + 1) * (nz + 1);
  const std::size_t interior_nodes = (nx - 1) * (ny - 1) * (nz - 1);
  EXPECT_EQ(s.vertices.size(), all_nodes - interior_nodes);
  EXPECT_NEAR(box_triangle_area(mesh, s, {1, 0, -1}, {3, 1, 2}), 2 * (2 + 3 + 6), 1e-12);
  for (int b : s.edge_body) EXPECT_EQ(b, 3);
  for (int b : s.vertex_body) EXPECT_EQ(b, 3);
  // An interior node is not a surface vertex.
  EXPECT_EQ(surface_vertex_index(s, 1 + (nx + 1) * (1 + (ny + 1) * 1)), -1);
  EXPECT_EQ(surface_vertex_index(s, 0), 0);
}

TEST(SurfaceMesh, TwoBodiesAreTwoSpheres) {
  HexMesh mesh = generate_box({1, 1, 1}, {2, 2, 2}, {0, 0, 0}, 0, "a");
  mesh.append(generate_box({1, 1, 1}, {1, 1, 1}, {2, 0, 0}, 1, "b"));
  const SurfaceMesh s = build_surface_mesh(mesh);
  EXPECT_EQ(expect_valid_closed_surface(mesh, s), 4);
  EXPECT_EQ(s.triangles.size(), 2u * (24 + 6));
  // Nodes of body b come after those of body a, and so do its edges and vertices.
  const auto first_b_node = static_cast<std::int64_t>(27);
  for (std::size_t e = 0; e < s.edges.size(); ++e) EXPECT_EQ(s.edge_body[e], s.edges[e][0] >= first_b_node ? 1 : 0);
  for (std::size_t v = 0; v < s.vertices.size(); ++v)
    EXPECT_EQ(s.vertex_body[v], s.vertices[v] >= first_b_node ? 1 : 0);
}

TEST(SurfaceMesh, CavityGivesASecondClosedSurface) {
  const HexMesh mesh = test::box_with_cavity(3);
  const SurfaceMesh s = build_surface_mesh(mesh);
  EXPECT_EQ(expect_valid_closed_surface(mesh, s), 4);
  EXPECT_EQ(s.vertices.size(), 56u + 8u);
}

TEST(SurfaceMesh, GluedBodiesShareRimPrimitivesWithTheLowerTriangle) {
  // Two elements of different bodies sharing the face x = 1: the rim of that face is used
  // by triangles of both bodies and takes the body of the lowest-numbered one (body 0's
  // element comes first).
  HexMesh mesh = generate_box({2, 1, 1}, {2, 1, 1}, {0, 0, 0}, 0, "bar");
  mesh.body = {0, 1};
  const SurfaceMesh s = build_surface_mesh(mesh);
  EXPECT_EQ(expect_valid_closed_surface(mesh, s), 2);
  for (std::size_t v = 0; v < s.vertices.size(); ++v) {
    const double x = mesh.nodes[s.vertices[v]][0];
    EXPECT_EQ(s.vertex_body[v], x < 1.5 ? 0 : 1) << "vertex at x = " << x;
  }
  for (std::size_t e = 0; e < s.edges.size(); ++e) {
    const double x0 = mesh.nodes[s.edges[e][0]][0], x1 = mesh.nodes[s.edges[e][1]][0];
    EXPECT_EQ(s.edge_body[e], std::min(x0, x1) < 0.5 || (x0 == 1 && x1 == 1) ? 0 : 1)
        << "edge from x = " << x0 << " to x = " << x1;
  }
}

TEST(SurfaceMesh, RequiresOneBodyIdPerElement) {
  HexMesh mesh = generate_box({1, 1, 1}, {2, 1, 1}, {0, 0, 0}, 0, "bar");
  mesh.body.pop_back();
  EXPECT_THROW(build_surface_mesh(mesh), MeshError);
}

}  // namespace
}  // namespace dipc
