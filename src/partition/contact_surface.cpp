// build_contact_surface (see contact_surface.hpp): triangles are rebuilt locally from the
// boundary-face masks with the same split rule rank 0 used to number them, so only their
// global ids travel; edges and vertices are copied from what rank 0 assigned to this rank.
#include "partition/contact_surface.hpp"

#include <string>

#include "mesh/boundary_faces.hpp"
#include "mesh/surface_mesh.hpp"
#include "partition/partition_error.hpp"

namespace dipc {
namespace {

std::string where() { return "build_contact_surface: "; }

void check_sizes(const DistributedMesh& mesh) {
  const OwnedSurface& s = mesh.owned_surface;
  const std::size_t ne = mesh.elements.size();
  if (mesh.boundary_face_mask.size() != ne || mesh.element_body.size() != ne) {
    throw PartitionError(where() + std::to_string(mesh.boundary_face_mask.size()) + " boundary face masks and " +
                         std::to_string(mesh.element_body.size()) + " body ids for " + std::to_string(ne) +
                         " elements (was the mesh made by distribute_mesh?)");
  }
  if (mesh.node_input_id.size() != mesh.local_to_global.size()) {
    throw PartitionError(where() + std::to_string(mesh.node_input_id.size()) + " input ids for " +
                         std::to_string(mesh.local_to_global.size()) + " local nodes");
  }
  if (s.edge_gid.size() != s.edges.size() || s.edge_body.size() != s.edges.size() ||
      s.vertex_gid.size() != s.vertices.size() || s.vertex_body.size() != s.vertices.size()) {
    throw PartitionError(where() + "owned_surface has " + std::to_string(s.edges.size()) + " edges with " +
                         std::to_string(s.edge_gid.size()) + " ids and " + std::to_string(s.edge_body.size()) +
                         " bodies, " + std::to_string(s.vertices.size()) + " vertices with " +
                         std::to_string(s.vertex_gid.size()) + " ids and " + std::to_string(s.vertex_body.size()) +
                         " bodies");
  }
}

void check_node(const DistributedMesh& mesh, std::int32_t node, const char* what, std::size_t index) {
  if (node < 0 || node >= mesh.num_local_nodes()) {
    throw PartitionError(where() + what + " " + std::to_string(index) + " has local node id " + std::to_string(node) +
                         ", outside [0, " + std::to_string(mesh.num_local_nodes()) + ")");
  }
}

void build_faces(const DistributedMesh& mesh, ContactSurface& surface) {
  const std::vector<std::int64_t>& gids = mesh.owned_surface.triangle_gid;
  for (std::size_t e = 0; e < mesh.elements.size(); ++e) {
    for (int f = 0; f < kHexFaces; ++f) {
      if (!(mesh.boundary_face_mask[e] & (1u << f))) continue;
      const std::array<int, 4> corners = hex_face_nodes(f);
      std::int32_t local[4];
      std::int64_t input[4];
      for (int i = 0; i < 4; ++i) {
        local[i] = mesh.elements[e][corners[i]];
        check_node(mesh, local[i], "local element", e);
        input[i] = mesh.node_input_id[static_cast<std::size_t>(local[i])];
      }
      const int m = quad_split_corner(input);
      for (int k = 0; k < 2; ++k) {
        const std::size_t t = surface.faces.size();
        if (t >= gids.size()) {
          throw PartitionError(where() + "the boundary face masks give more triangles than the " +
                               std::to_string(gids.size()) + " triangle ids received");
        }
        const std::array<int, 3> c = quad_triangle_corners(m, k);
        surface.faces.push_back({local[c[0]], local[c[1]], local[c[2]]});
        surface.face_body.push_back(mesh.element_body[e]);
        surface.face_gid.push_back(gids[t]);
        surface.face_element.push_back(static_cast<std::int32_t>(e));
      }
    }
  }
  if (surface.faces.size() != gids.size()) {
    throw PartitionError(where() + "the boundary face masks give " + std::to_string(surface.faces.size()) +
                         " triangles but " + std::to_string(gids.size()) + " triangle ids were received");
  }
}

}  // namespace

ContactSurface build_contact_surface(const DistributedMesh& mesh) {
  check_sizes(mesh);
  const OwnedSurface& owned = mesh.owned_surface;
  ContactSurface surface;
  surface.num_global_vertices = owned.num_global_vertices;
  surface.num_global_edges = owned.num_global_edges;
  surface.num_global_faces = owned.num_global_triangles;
  build_faces(mesh, surface);
  for (std::size_t k = 0; k < owned.edges.size(); ++k) {
    check_node(mesh, owned.edges[k][0], "owned edge", k);
    check_node(mesh, owned.edges[k][1], "owned edge", k);
  }
  for (std::size_t k = 0; k < owned.vertices.size(); ++k) {
    check_node(mesh, owned.vertices[k], "owned vertex", k);
  }
  surface.edges = owned.edges;
  surface.edge_gid = owned.edge_gid;
  surface.edge_body = owned.edge_body;
  surface.vertices = owned.vertices;
  surface.vertex_gid = owned.vertex_gid;
  surface.vertex_body = owned.vertex_body;
  return surface;
}

}  // namespace dipc
