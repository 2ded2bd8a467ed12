// assign_surface_owners (see surface_owners.hpp): one pass over the triangles, taking the
// minimum triangle owner per edge and per vertex.
#include "partition/surface_owners.hpp"

#include <algorithm>
#include <climits>
#include <string>

#include "partition/partition_error.hpp"

namespace dipc {

SurfaceOwners assign_surface_owners(const SurfaceMesh& surface, const std::vector<int>& element_part) {
  SurfaceOwners owners;
  owners.triangle.resize(surface.triangles.size());
  owners.edge.assign(surface.edges.size(), INT_MAX);
  owners.vertex.assign(surface.vertices.size(), INT_MAX);
  for (std::size_t t = 0; t < surface.triangles.size(); ++t) {
    const std::int64_t element = surface.quads[t / 2].element;
    if (element < 0 || static_cast<std::size_t>(element) >= element_part.size()) {
      throw PartitionError("assign_surface_owners: surface triangle " + std::to_string(t) + " belongs to element " +
                           std::to_string(element) + " but only " + std::to_string(element_part.size()) +
                           " elements have a part");
    }
    const int part = element_part[static_cast<std::size_t>(element)];
    owners.triangle[t] = part;
    for (int i = 0; i < 3; ++i) {
      int& edge_owner = owners.edge[static_cast<std::size_t>(surface.triangle_edges[t][i])];
      edge_owner = std::min(edge_owner, part);
      const std::int64_t v = surface_vertex_index(surface, surface.triangles[t][i]);
      int& vertex_owner = owners.vertex[static_cast<std::size_t>(v)];
      vertex_owner = std::min(vertex_owner, part);
    }
  }
  return owners;
}

}  // namespace dipc
