// build_contact_surface under MPI (1, 2 and 3 ranks) against the serial surface of the whole
// mesh (build_surface_mesh, which every rank computes from its own copy of the input):
// boundary-face masks, each triangle / edge / vertex owned by exactly one rank, the union of
// the owned primitives gathered to rank 0 equal to the serial surface, global ids dense and
// equal to the serial positions (so independent of the rank count), the ownership rule for
// edges and vertices, local node ids that are valid, and determinism.
#include "partition/contact_surface.hpp"

#include <gtest/gtest.h>
#include <petscsys.h>

#include <algorithm>
#include <climits>
#include <vector>

#include "box_mesh.hpp"
#include "distributed_mesh_checks.hpp"
#include "mesh/surface_mesh.hpp"
#include "partition/partition_error.hpp"

namespace dipc {
namespace {

using Triple = std::array<std::int64_t, 3>;
using Pair = std::array<std::int64_t, 2>;

HexMesh box_with_cavity(int n) {
  HexMesh mesh = test::structured_box(n, n, n);
  const int c = n / 2;
  const auto centre = static_cast<std::ptrdiff_t>(c + n * (c + n * c));
  mesh.hexes.erase(mesh.hexes.begin() + centre);
  mesh.body.erase(mesh.body.begin() + centre);
  return mesh;
}

// Rotates a triangle so its smallest id comes first, keeping its orientation.
Triple canonical(const Triple& t) {
  const auto m = std::min_element(t.begin(), t.end()) - t.begin();
  return {t[m], t[(m + 1) % 3], t[(m + 2) % 3]};
}

// Every rank's values, concatenated in rank order on rank 0 (empty elsewhere).
std::vector<std::int64_t> gather_to_root(const std::vector<std::int64_t>& mine, MPI_Comm comm) {
  const int size = test::size_of(comm);
  int count = static_cast<int>(mine.size());
  std::vector<int> counts(size), displs(size, 0);
  MPI_Gather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, comm);
  for (int r = 1; r < size; ++r) displs[r] = displs[r - 1] + counts[r - 1];
  std::vector<std::int64_t> all(test::rank_of(comm) == 0 ? displs.back() + counts.back() : 0);
  MPI_Gatherv(mine.data(), count, MPI_INT64_T, all.data(), counts.data(), displs.data(), MPI_INT64_T, 0, comm);
  return all;
}

// The gathered union of owned primitives (as input node ids) is the serial surface with
// each primitive once; this check does not use the global ids.
void expect_union_is_serial_surface(const DistributedMesh& part, const ContactSurface& cs, const SurfaceMesh& serial) {
  const auto input = [&](std::int32_t local) { return part.node_input_id.at(local); };
  std::vector<std::int64_t> flat_triangles, flat_edges, flat_vertices;
  for (const auto& f : cs.faces) {
    const Triple t = canonical({input(f[0]), input(f[1]), input(f[2])});
    flat_triangles.insert(flat_triangles.end(), t.begin(), t.end());
  }
  for (const auto& e : cs.edges) {
    flat_edges.push_back(std::min(input(e[0]), input(e[1])));
    flat_edges.push_back(std::max(input(e[0]), input(e[1])));
  }
  for (std::int32_t v : cs.vertices) flat_vertices.push_back(input(v));
  flat_triangles = gather_to_root(flat_triangles, part.comm);
  flat_edges = gather_to_root(flat_edges, part.comm);
  flat_vertices = gather_to_root(flat_vertices, part.comm);
  if (test::rank_of(part.comm) != 0) return;

  std::vector<Triple> triangles, expected_triangles;
  for (std::size_t i = 0; i + 2 < flat_triangles.size(); i += 3) {
    triangles.push_back({flat_triangles[i], flat_triangles[i + 1], flat_triangles[i + 2]});
  }
  for (const Triple& t : serial.triangles) expected_triangles.push_back(canonical(t));
  std::sort(triangles.begin(), triangles.end());
  std::sort(expected_triangles.begin(), expected_triangles.end());
  EXPECT_EQ(triangles, expected_triangles);

  std::vector<Pair> edges;
  for (std::size_t i = 0; i + 1 < flat_edges.size(); i += 2) {
    edges.push_back({flat_edges[i], flat_edges[i + 1]});
  }
  std::sort(edges.begin(), edges.end());
  EXPECT_EQ(edges, serial.edges);  // serial.edges is sorted and unique

  std::sort(flat_vertices.begin(), flat_vertices.end());
  EXPECT_EQ(flat_vertices, serial.vertices);
}

void expect_surface_matches_serial(const HexMesh& mesh) {
  MPI_Comm comm = PETSC_COMM_WORLD;
  const int rank = test::rank_of(comm);
  const DistributedMesh part = test::distribute_from_root(mesh, comm);
  const ContactSurface cs = build_contact_surface(part);
  const SurfaceMesh serial = build_surface_mesh(mesh);
  const auto input = [&](std::int32_t local) { return part.node_input_id.at(local); };

  // Masks: exactly the serial boundary faces of each local element.
  std::vector<std::uint8_t> serial_mask(mesh.num_elements(), 0);
  for (const BoundaryFace& q : serial.quads) serial_mask[q.element] |= 1u << q.face;
  ASSERT_EQ(part.boundary_face_mask.size(), part.elements.size());
  for (int e = 0; e < part.num_elements(); ++e) {
    EXPECT_EQ(part.boundary_face_mask[e], serial_mask[part.element_input_id[e]])
        << "input element " << part.element_input_id[e];
  }

  ASSERT_EQ(cs.num_global_faces, static_cast<std::int64_t>(serial.triangles.size()));
  ASSERT_EQ(cs.num_global_edges, static_cast<std::int64_t>(serial.edges.size()));
  ASSERT_EQ(cs.num_global_vertices, static_cast<std::int64_t>(serial.vertices.size()));
  ASSERT_EQ(cs.face_body.size(), cs.faces.size());
  ASSERT_EQ(cs.face_gid.size(), cs.faces.size());
  ASSERT_EQ(cs.face_element.size(), cs.faces.size());
  ASSERT_EQ(cs.edge_body.size(), cs.edges.size());
  ASSERT_EQ(cs.edge_gid.size(), cs.edges.size());
  ASSERT_EQ(cs.vertex_body.size(), cs.vertices.size());
  ASSERT_EQ(cs.vertex_gid.size(), cs.vertices.size());

  // Triangles: the serial triangle of the same global id, same orientation and split.
  std::vector<std::int64_t> face_count(serial.triangles.size(), 0);
  std::vector<int> lowest_rank_using_edge(serial.edges.size(), INT_MAX);
  std::vector<int> lowest_rank_using_vertex(serial.vertices.size(), INT_MAX);
  for (std::size_t t = 0; t < cs.faces.size(); ++t) {
    const std::int64_t g = cs.face_gid[t];
    ASSERT_GE(g, 0);
    ASSERT_LT(g, cs.num_global_faces);
    ++face_count[g];
    const auto& f = cs.faces[t];
    EXPECT_EQ((Triple{input(f[0]), input(f[1]), input(f[2])}), serial.triangles[g]) << "triangle gid " << g;
    EXPECT_EQ(cs.face_body[t], serial.triangle_body[g]);
    EXPECT_EQ(part.element_input_id.at(cs.face_element[t]), serial.quads[g / 2].element);
    for (int i = 0; i < 3; ++i) {
      auto& edge_rank = lowest_rank_using_edge[serial.triangle_edges[g][i]];
      edge_rank = std::min(edge_rank, rank);
      auto& vertex_rank = lowest_rank_using_vertex[surface_vertex_index(serial, serial.triangles[g][i])];
      vertex_rank = std::min(vertex_rank, rank);
    }
  }
  lowest_rank_using_edge = test::allreduce(lowest_rank_using_edge, MPI_INT, MPI_MIN, comm);
  lowest_rank_using_vertex = test::allreduce(lowest_rank_using_vertex, MPI_INT, MPI_MIN, comm);

  // Edges and vertices: the serial primitive of the same global id, owned by the lowest
  // rank that holds a triangle using it.
  std::vector<std::int64_t> edge_count(serial.edges.size(), 0);
  for (std::size_t k = 0; k < cs.edges.size(); ++k) {
    const std::int64_t g = cs.edge_gid[k];
    ASSERT_GE(g, 0);
    ASSERT_LT(g, cs.num_global_edges);
    ++edge_count[g];
    for (std::int32_t node : cs.edges[k]) {
      ASSERT_GE(node, 0);
      ASSERT_LT(node, part.num_local_nodes());
    }
    EXPECT_EQ((Pair{input(cs.edges[k][0]), input(cs.edges[k][1])}), serial.edges[g]);
    EXPECT_EQ(cs.edge_body[k], serial.edge_body[g]);
    EXPECT_EQ(lowest_rank_using_edge[g], rank) << "edge gid " << g;
  }
  std::vector<std::int64_t> vertex_count(serial.vertices.size(), 0);
  for (std::size_t k = 0; k < cs.vertices.size(); ++k) {
    const std::int64_t g = cs.vertex_gid[k];
    ASSERT_GE(g, 0);
    ASSERT_LT(g, cs.num_global_vertices);
    ++vertex_count[g];
    ASSERT_GE(cs.vertices[k], 0);
    ASSERT_LT(cs.vertices[k], part.num_local_nodes());
    EXPECT_EQ(input(cs.vertices[k]), serial.vertices[g]);
    EXPECT_EQ(cs.vertex_body[k], serial.vertex_body[g]);
    EXPECT_EQ(lowest_rank_using_vertex[g], rank) << "vertex gid " << g;
  }
  EXPECT_TRUE(std::is_sorted(cs.edge_gid.begin(), cs.edge_gid.end()));
  EXPECT_TRUE(std::is_sorted(cs.vertex_gid.begin(), cs.vertex_gid.end()));

  // Each global id on exactly one rank.
  face_count = test::allreduce(face_count, MPI_INT64_T, MPI_SUM, comm);
  edge_count = test::allreduce(edge_count, MPI_INT64_T, MPI_SUM, comm);
  vertex_count = test::allreduce(vertex_count, MPI_INT64_T, MPI_SUM, comm);
  for (std::size_t g = 0; g < face_count.size(); ++g) EXPECT_EQ(face_count[g], 1) << g;
  for (std::size_t g = 0; g < edge_count.size(); ++g) EXPECT_EQ(edge_count[g], 1) << g;
  for (std::size_t g = 0; g < vertex_count.size(); ++g) EXPECT_EQ(vertex_count[g], 1) << g;

  expect_union_is_serial_surface(part, cs, serial);
}

TEST(ContactSurface, BoxMatchesTheSerialSurface) { expect_surface_matches_serial(test::structured_box(6, 4, 3)); }

TEST(ContactSurface, TwoBodiesMatchTheSerialSurface) { expect_surface_matches_serial(test::two_body_mesh()); }

TEST(ContactSurface, CavityMatchesTheSerialSurface) { expect_surface_matches_serial(box_with_cavity(5)); }

TEST(ContactSurface, CutFacesAreNotBoundary) {
  // A face on the cut between two ranks is the only face of its element on that rank but
  // has an element on the other side in the whole mesh: no rank may mark it. Over all ranks
  // the marked faces are then exactly the 2 (nx ny + ny nz + nx nz) faces of the box.
  const HexMesh mesh = test::structured_box(6, 4, 3);
  const DistributedMesh part = test::distribute_from_root(mesh, PETSC_COMM_WORLD);
  std::int64_t counts[2] = {0, part.num_ghost_nodes()};
  for (std::uint8_t m : part.boundary_face_mask) {
    for (int f = 0; f < 6; ++f) counts[0] += (m >> f) & 1;
  }
  MPI_Allreduce(MPI_IN_PLACE, counts, 2, MPI_INT64_T, MPI_SUM, PETSC_COMM_WORLD);
  EXPECT_EQ(counts[0], 2 * (6 * 4 + 4 * 3 + 6 * 3));
  if (test::size_of(PETSC_COMM_WORLD) > 1) {
    EXPECT_GT(counts[1], 0) << "the box was not cut, so there is no cut face to test";
  }
}

TEST(ContactSurface, SameInputGivesSameSurface) {
  const HexMesh mesh = box_with_cavity(3);
  const ContactSurface a = build_contact_surface(test::distribute_from_root(mesh, PETSC_COMM_WORLD));
  const ContactSurface b = build_contact_surface(test::distribute_from_root(mesh, PETSC_COMM_WORLD));
  EXPECT_EQ(a.faces, b.faces);
  EXPECT_EQ(a.face_gid, b.face_gid);
  EXPECT_EQ(a.edges, b.edges);
  EXPECT_EQ(a.edge_gid, b.edge_gid);
  EXPECT_EQ(a.vertices, b.vertices);
  EXPECT_EQ(a.vertex_gid, b.vertex_gid);
}

TEST(ContactSurface, InconsistentMeshIsRejected) {
  DistributedMesh part = test::distribute_from_root(test::structured_box(6, 4, 3), PETSC_COMM_WORLD);
  DistributedMesh no_masks = part;
  no_masks.boundary_face_mask.clear();
  EXPECT_THROW(build_contact_surface(no_masks), PartitionError);

  DistributedMesh missing_ids = part;
  missing_ids.owned_surface.triangle_gid.push_back(0);
  EXPECT_THROW(build_contact_surface(missing_ids), PartitionError);

  if (!part.owned_surface.edges.empty()) {
    DistributedMesh bad_edge = part;
    bad_edge.owned_surface.edges[0][1] = part.num_local_nodes();
    EXPECT_THROW(build_contact_surface(bad_edge), PartitionError);
  }
}

}  // namespace
}  // namespace dipc
