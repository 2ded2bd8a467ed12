// Reader for Gmsh MSH 4.1 ASCII files holding linear hexahedra: the mesh files that scene
// bodies name. Format reference: Gmsh reference manual, section "MSH file format"
// (version 4.1).
#pragma once
#include <string>

#include "mesh/hex_mesh.hpp"

namespace dipc {

// Reads the hexahedra (element type 5) of `path` with every element's body id set to `body`.
// Nodes keep the order of $Nodes, elements the order of $Elements. Each physical group, of
// any dimension, becomes a node set holding the nodes of its elements (points, lines,
// triangles, quadrangles and hexahedra); the set is named from $PhysicalNames, or
// "physical_<tag>" for a group without a name. Groups of different dimensions that share an
// explicit name are merged into one set; an unnamed group whose "physical_<tag>" would
// collide with another group is an error. Unknown sections ($Periodic, $NodeData, ...) are
// skipped. The result has passed check_mesh, with messages that use the file's tags.
//
// Throws MeshError "<path>:<line>: <what>" for: an unreadable file, binary files, MSH versions
// other than 4.1, partitioned meshes, element types other than points/lines/triangles/quads/
// linear hexahedra, truncated or malformed sections, duplicate or unknown node tags,
// non-finite coordinates, a file without hexahedra, a negative body id, and every
// check_mesh failure (inverted or degenerate element, unused node, ...).
HexMesh read_gmsh(const std::string& path, int body);

}  // namespace dipc
