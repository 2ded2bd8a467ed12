// Tests of assign_surface_owners on hand-chosen and random element partitions: triangles go
// to their element's part, edges and vertices to the lowest part holding a triangle that
// uses them (checked by brute force over all triangles), including a re-entrant corner
// whose node owner has no triangle there.
#include "partition/surface_owners.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <climits>
#include <random>

#include "box_mesh.hpp"
#include "partition/partition_error.hpp"
#include "partition/partition_numbering.hpp"

namespace dipc {
namespace {

// 3 x 3 x 3 unit cubes without the centre one (element 13): a cavity whose corners are
// touched by the box's corner elements only through a corner.
HexMesh box_with_cavity() {
  HexMesh mesh = test::structured_box(3, 3, 3);
  mesh.hexes.erase(mesh.hexes.begin() + 13);
  mesh.body.erase(mesh.body.begin() + 13);
  return mesh;
}

// Lowest part among the triangles using edge (a, b) or, with b < 0, vertex a; INT_MAX if
// no triangle uses it.
int lowest_part_using(const SurfaceMesh& s, const SurfaceOwners& owners, std::int64_t a, std::int64_t b) {
  int lowest = INT_MAX;
  for (std::size_t t = 0; t < s.triangles.size(); ++t) {
    const auto& tri = s.triangles[t];
    const bool has_a = std::find(tri.begin(), tri.end(), a) != tri.end();
    const bool has_b = b < 0 || std::find(tri.begin(), tri.end(), b) != tri.end();
    if (has_a && has_b) lowest = std::min(lowest, owners.triangle[t]);
  }
  return lowest;
}

void expect_owner_rules(const HexMesh& mesh, const std::vector<int>& element_part) {
  const SurfaceMesh s = build_surface_mesh(mesh);
  const SurfaceOwners owners = assign_surface_owners(s, element_part);
  ASSERT_EQ(owners.triangle.size(), s.triangles.size());
  ASSERT_EQ(owners.edge.size(), s.edges.size());
  ASSERT_EQ(owners.vertex.size(), s.vertices.size());
  for (std::size_t t = 0; t < s.triangles.size(); ++t) {
    EXPECT_EQ(owners.triangle[t], element_part[s.quads[t / 2].element]) << "triangle " << t;
  }
  for (std::size_t e = 0; e < s.edges.size(); ++e) {
    EXPECT_EQ(owners.edge[e], lowest_part_using(s, owners, s.edges[e][0], s.edges[e][1])) << "edge " << e;
  }
  for (std::size_t v = 0; v < s.vertices.size(); ++v) {
    EXPECT_EQ(owners.vertex[v], lowest_part_using(s, owners, s.vertices[v], -1)) << "vertex " << v;
  }
}

TEST(SurfaceOwners, CavityCornerGoesToAPartWithATriangleNotToTheNodeOwner) {
  const HexMesh mesh = box_with_cavity();
  // Element 0 (the cube at the origin, part 0) touches cavity corner (1, 1, 1) only through
  // its own corner; every other element is in part 1.
  std::vector<int> element_part(mesh.num_elements(), 1);
  element_part[0] = 0;
  const std::int64_t corner = 1 + 4 * (1 + 4 * 1);
  const PartitionNumbering numbering = number_partition(mesh, element_part, 2);
  ASSERT_EQ(numbering.node_owner[corner], 0);

  const SurfaceMesh s = build_surface_mesh(mesh);
  const SurfaceOwners owners = assign_surface_owners(s, element_part);
  const std::int64_t v = surface_vertex_index(s, corner);
  ASSERT_GE(v, 0);
  EXPECT_EQ(owners.vertex[v], 1);
  // Node (1, 0, 0) is on element 0's faces y = 0 and z = 0: part 0 holds it.
  EXPECT_EQ(owners.vertex[surface_vertex_index(s, 1)], 0);
  expect_owner_rules(mesh, element_part);
}

TEST(SurfaceOwners, RandomPartitionsFollowTheRules) {
  std::mt19937 rng(2024);
  const HexMesh meshes[] = {test::structured_box(4, 3, 2), test::two_body_mesh(), box_with_cavity()};
  for (const HexMesh& mesh : meshes) {
    for (int num_parts : {1, 2, 3, 5}) {
      std::uniform_int_distribution<int> pick(0, num_parts - 1);
      std::vector<int> element_part(mesh.num_elements());
      for (int& p : element_part) p = pick(rng);
      expect_owner_rules(mesh, element_part);
    }
  }
}

TEST(SurfaceOwners, MissingElementPartIsAnError) {
  const HexMesh mesh = test::structured_box(2, 1, 1);
  const SurfaceMesh s = build_surface_mesh(mesh);
  EXPECT_THROW(assign_surface_owners(s, std::vector<int>(1, 0)), PartitionError);
}

}  // namespace
}  // namespace dipc
