// TriangleSurface: a triangle surface read from an OBJ or STL file (obstacles, closed shapes
// for the voxeliser). Open surfaces are allowed; closedness is the caller's concern
// (check_closed_surface in mesh/closed_surface.hpp).
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "mesh/hex_mesh.hpp"

namespace dipc {

using Triangle = std::array<std::int64_t, 3>;

struct TriangleSurface {
  std::string source;               // the file path, used in messages
  std::vector<Vec3> vertices;       // every vertex is used by at least one triangle
  std::vector<Triangle> triangles;  // 0-based vertex ids, in the file's corner order
  // Where triangle t came from: the file line of its face (OBJ, ASCII STL: the line of the
  // face's first vertex) or, for binary STL, the 0-based facet index. Polygons give several
  // triangles with the same origin. describe_triangle() turns it into text.
  std::vector<std::int64_t> triangle_origin;
  bool binary = false;  // origins are facet indices (binary STL), not lines
};

// "<source>:<line>" or "<source>: facet <index>" for triangle t, for messages.
std::string describe_triangle(const TriangleSurface& surface, std::size_t t);

}  // namespace dipc
