// Bodies that lie inside other bodies. Two surfaces that do not cross can still be nested, and
// then no edge crosses a triangle and no distance is zero, so the contact checks of the
// initial state pass while the inner body is in fact inside the outer one's material. With
// contact such a state has no meaning (the barrier keeps the inner body in), so dipc refuses it.
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "mesh/hex_mesh.hpp"

namespace dipc {

struct NestedBodies {
  int inner = -1, outer = -1;  // body ids; inner = -1 when no body lies inside another
  std::int64_t node = -1;      // a surface node of `inner` enclosed by `outer`'s surface
};

// Finds a body that lies inside another one. For each pair whose bounding boxes nest, a few
// surface vertices of the smaller are tested against the closed boundary surface of the other
// (generalised winding number, 1 inside, 0 outside, so a point in a cavity is outside); a
// vertex that lies on that surface (winding number near ½) decides nothing and the next is
// tried. Needs one body id per element; surfaces that cross are not looked for here (the
// contact check of the initial state reports them).
NestedBodies find_nested_bodies(const HexMesh& mesh);

// Throws MeshError "<source>: body "inner" lies inside body "outer" (...)" when
// find_nested_bodies finds a pair; `body_names` is indexed by body id.
void check_no_nested_bodies(const HexMesh& mesh, const std::vector<std::string>& body_names, const std::string& source);

// Generalised winding number of the closed, outward-oriented triangle surface `triangles` at
// `point` (Σ solid angles / 4π): 1 inside, 0 outside, about ½ on the surface.
double winding_number(const HexMesh& mesh, const std::vector<std::array<std::int64_t, 3>>& triangles,
                      const Vec3& point);

}  // namespace dipc
