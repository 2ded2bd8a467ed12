// Checks that a triangle surface bounds a volume: closed, manifold along its edges and
// consistently oriented. The voxeliser needs this; obstacles do not (they may be open).
#pragma once
#include "mesh/triangle_surface.hpp"

namespace dipc {

// Throws MeshError "<source>: <what>", naming an offending edge by its end points and the
// file locations (describe_triangle) of the triangles on it, unless every edge (pair of
// vertex ids) is shared by exactly two triangles that traverse it in opposite directions.
// Edges are examined in order of their vertex ids, so the edge named is the same on every
// run. Several closed components, nested or not, pass.
void check_closed_surface(const TriangleSurface& surface);

// Volume enclosed by a closed surface, by the divergence theorem: 1/6 Σ a · (b × c) over the
// triangles (a, b, c). Positive when the triangles face outward, negative when inward.
double signed_enclosed_volume(const TriangleSurface& surface);

}  // namespace dipc
