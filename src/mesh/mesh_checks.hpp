// Validation of a whole HexMesh before it is partitioned: everything downstream (element
// loops, METIS, the PETSc numbering) assumes a mesh that passes check_mesh.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "mesh/hex_mesh.hpp"

namespace dipc {

// Where each node and element of a mesh came from in a file, so that check_mesh can name
// them as the file does. Every vector is indexed by the 0-based id; an empty vector means
// "not known" and the 0-based id is reported instead.
struct MeshSourceMap {
  std::vector<std::int64_t> node_tags;      // file tag of node i
  std::vector<std::int64_t> node_lines;     // 1-based line where node i's tag is
  std::vector<std::int64_t> element_tags;   // file tag of element e
  std::vector<std::int64_t> element_lines;  // 1-based line of element e
  // Binary files have no lines: node_lines and element_lines then hold byte offsets, and
  // messages say "<source>: byte <offset>: ".
  bool byte_offsets = false;
};

// An element whose smallest det J (hex8::min_jacobian_determinant) is at most this
// fraction of (longest edge)^3 is degenerate rather than merely distorted. A cube of edge h
// has det J = h^3/8, so 1e-12 is far below any usable element and far above round-off.
constexpr double kDegenerateJacobianRatio = 1e-12;

// Throws MeshError, with a message starting "<source>: " (or "<source>:<line>: " when
// `map` knows the line, "<source>: byte <offset>: " for a binary file), unless:
//   - there is at least one element and one body id per element, every body id >= 0;
//   - every coordinate is finite;
//   - every element's node ids are in range and distinct;
//   - every element has min det J > kDegenerateJacobianRatio * (longest edge)^3 (the
//     message says "inverted" for det J < 0, otherwise "degenerate", with the value and
//     the corner or Gauss point where the minimum is);
//   - every node is used by some element;
//   - every node set holds sorted, unique, in-range ids.
// Ids in messages are 0-based ("node 4", "element 2") unless `map` gives the file's tags
// ("node 17", "element 9 (hexahedron)").
void check_mesh(const HexMesh& mesh, const std::string& source, const MeshSourceMap* map = nullptr);

// Length of the diagonal of the axis-aligned box around all nodes (0 for no nodes); the
// length scale for relative tolerances (contact d̂, selection boxes).
double bounding_box_diagonal(const HexMesh& mesh);

}  // namespace dipc
