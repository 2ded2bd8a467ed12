// HexMesh::append: concatenation of meshes of several bodies into the one mesh that is
// partitioned. Node ids of the appended mesh are shifted past the existing nodes.
#include "mesh/hex_mesh.hpp"

#include "mesh/mesh_error.hpp"

namespace dipc {

void HexMesh::append(const HexMesh& other) {
  // Validate everything before touching *this so a failed append leaves it unchanged.
  if (body.size() != hexes.size() || other.body.size() != other.hexes.size())
    throw MeshError("HexMesh::append: each mesh needs one body id per element (have " + std::to_string(body.size()) +
                    " for " + std::to_string(hexes.size()) + " elements and " + std::to_string(other.body.size()) +
                    " for " + std::to_string(other.hexes.size()) + ")");
  for (const auto& [name, ids] : other.node_sets)
    if (node_sets.count(name) != 0)
      throw MeshError("HexMesh::append: node set '" + name + "' exists in both meshes; selection names must be unique");

  const auto offset = static_cast<std::int64_t>(nodes.size());
  nodes.insert(nodes.end(), other.nodes.begin(), other.nodes.end());
  hexes.reserve(hexes.size() + other.hexes.size());
  for (Hex h : other.hexes) {
    for (auto& n : h) n += offset;
    hexes.push_back(h);
  }
  body.insert(body.end(), other.body.begin(), other.body.end());
  for (const auto& [name, ids] : other.node_sets) {
    auto& shifted = node_sets[name];
    shifted.reserve(ids.size());
    for (std::int64_t n : ids) shifted.push_back(n + offset);  // order-preserving: stays sorted
  }
}

}  // namespace dipc
