// Structured box meshes: the generated bodies of a scene ("box" in the scene file) and the
// meshes most tests build on.
#pragma once
#include <array>
#include <string>

#include "mesh/hex_mesh.hpp"

namespace dipc {

// A box [origin, origin + size] cut into resolution[0] x resolution[1] x resolution[2]
// equal hexahedra (Gmsh node ordering, positive orientation: det J > 0 everywhere).
// Node (i, j, k) has id i + (nx+1) * (j + (ny+1) * k); element (i, j, k) has id
// i + nx * (j + ny * k). Every element gets body id `body`.
// Node sets: "<name>" (all nodes) and "<name>.xmin", ".xmax", ".ymin", ".ymax", ".zmin",
// ".zmax" (the nodes on each face).
// Throws MeshError for a resolution < 1, a size <= 0 or non-finite, a non-finite origin,
// a negative body id, an empty name, or a node count that does not fit in 64-bit ids.
HexMesh generate_box(const std::array<double, 3>& size, const std::array<int, 3>& resolution,
                     const std::array<double, 3>& origin, int body, const std::string& name);

}  // namespace dipc
