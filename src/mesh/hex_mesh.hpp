// HexMesh: a whole (undistributed) hexahedral mesh as read from a file or generated,
// before partitioning. Node ordering of each hex follows Gmsh/VTK/XDMF:
//   0:(-1,-1,-1) 1:(+1,-1,-1) 2:(+1,+1,-1) 3:(-1,+1,-1)
//   4:(-1,-1,+1) 5:(+1,-1,+1) 6:(+1,+1,+1) 7:(-1,+1,+1)   (reference coordinates ξ,η,ζ)
#pragma once
#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace dipc {

using Vec3 = std::array<double, 3>;
using Hex = std::array<std::int64_t, 8>;

struct HexMesh {
  std::vector<Vec3> nodes;  // reference coordinates, node ids are 0-based indices
  std::vector<Hex> hexes;   // 8 node ids per element
  std::vector<int> body;    // body id per element (index into the scene's bodies)
  // Named node sets (Gmsh physical groups of any dimension, generator faces such as
  // "beam.xmin"); sorted, unique node ids.
  std::map<std::string, std::vector<std::int64_t>> node_sets;

  std::size_t num_nodes() const { return nodes.size(); }
  std::size_t num_elements() const { return hexes.size(); }

  // Appends `other` (its node ids shifted, its selections kept with their names; a name
  // present in both is an error because selections must be unambiguous).
  void append(const HexMesh& other);
};

}  // namespace dipc
