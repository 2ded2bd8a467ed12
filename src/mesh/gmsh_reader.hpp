// Reader for Gmsh MSH files holding linear hexahedra: the mesh files that scene bodies name.
// Versions 4.1 and 2.2, ASCII and binary (little-endian; the writer's size_t of 4 or 8 bytes
// in 4.1). Format reference: Gmsh reference manual, sections "MSH file format" (4.1) and
// "Legacy formats" (2.2).
#pragma once
#include <string>

#include "mesh/hex_mesh.hpp"

namespace dipc {

// Reads the hexahedra (element type 5) of `path` with every element's body id set to `body`. Nodes
// keep the order of $Nodes, elements the order of $Elements. Each physical group, of any dimension,
// becomes a node set holding the nodes of its elements (points, lines, triangles, quadrangles and
// hexahedra; in MSH 2.2 the element's first tag); the set is named from $PhysicalNames, or
// "physical_<tag>" for a group without a name. Groups of different dimensions that share an
// explicit name are merged into one set; an unnamed group whose "physical_<tag>" would collide with
// another group is an error. Unknown sections ($Periodic, $NodeData, ...) are skipped. MSH 2.2
// repeats an element once per physical group of its entity; a hexahedron with the same nodes in the
// same order as an earlier one is that element again. Partition tags of MSH 2.2 elements are
// ignored (dipc partitions the mesh itself). The result has passed check_mesh, with messages that
// use the file's tags.
//
// Throws MeshError "<path>:<line>: <what>" (ASCII) or "<path>: byte <offset>: <what>" (past the
// $MeshFormat of a binary file) for: an unreadable file, MSH versions other than 4.1 and 2.2,
// big-endian binary files, a binary data size other than 4/8 (4.1) or 8 (2.2), partitioned 4.1
// meshes, a hexahedron repeated with its nodes in another order (2.2), element types other than
// points/lines/triangles/quads/linear hexahedra, truncated or malformed sections, duplicate or
// unknown node tags, non-finite coordinates, a file without hexahedra, a negative body id, and
// every check_mesh failure (inverted or degenerate element, unused node, ...).
HexMesh read_gmsh(const std::string& path, int body);

}  // namespace dipc
