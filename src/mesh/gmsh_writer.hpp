// Writer of Gmsh MSH 4.1 ASCII files, the format read_gmsh reads (gmsh_reader.hpp): what
// dipc-voxelize produces, so that scene files can refer to it.
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "mesh/hex_mesh.hpp"

namespace dipc {

// A named group of quadrangles (4 node ids, counter-clockwise seen from outside), written as
// a physical surface: read back, it becomes the node set `name`.
struct QuadGroup {
  std::string name;
  std::vector<std::array<std::int64_t, 4>> quads;
};

// Writes the nodes and hexahedra of `mesh` (node tags = id + 1, hexahedra in a physical volume
// named `volume_name`) and one physical surface per group. Coordinates are written as the
// shortest text that reads back as the same double, so they read back bit for bit. Throws
// MeshError when the file cannot be written or a group name is empty or contains '"'.
void write_gmsh(const std::string& path, const HexMesh& mesh, const std::string& volume_name,
                const std::vector<QuadGroup>& groups);

}  // namespace dipc
