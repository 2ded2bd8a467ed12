// Readers for triangle surfaces in Wavefront OBJ and STL (ASCII and binary) files.
//
// OBJ (Wavefront "Object Files (.obj)" specification, Appendix B1 of the Advanced Visualizer
// manual): `v x y z [w]` vertices (w must be 1 when given; six numbers `v x y z r g b`, the
// common vertex-colour extension, are accepted and the colour ignored) and `f` faces whose
// corners are `v`, `v/vt`, `v//vn` or `v/vt/vn`. Vertex references are 1-based, or negative
// for "relative to the last vertex defined so far" (-1 is the latest). A face with n > 3
// corners is fan-triangulated from its first corner: (0,1,2), (0,2,3), ... which is exact for
// the planar convex polygons exporters write. Texture/normal data, groups, objects, smoothing
// and material statements are ignored; free-form geometry, lines and points are refused.
//
// STL (3D Systems "StereoLithography Interface Specification", 1989): binary is an 80-byte
// header, a little-endian uint32 facet count and 50 bytes per facet (normal, 3 vertices as
// little-endian float32, a 2-byte attribute); ASCII is `solid name`, then per facet
// `facet normal nx ny nz / outer loop / vertex x y z (x3) / endloop / endfacet`, then
// `endsolid`. A file is binary when its size is exactly 84 + 50 x count (some binary headers
// start with "solid", so the first word cannot decide). Normals are ignored: the orientation
// is the corner order, as the specification's right-hand rule makes them agree.
//
// Both formats: vertices with equal coordinates are merged into one (STL repeats every
// corner; OBJ exporters split vertices at texture seams), in order of first appearance, and
// vertices no face uses are dropped, so the surface's connectivity is its geometry's.
//
// Checked on load, with MeshError "<path>:<line>: <what>" (ASCII) or
// "<path>: facet <i> (byte <offset>): <what>" (binary STL): unreadable or empty files,
// unknown statements, malformed or non-finite numbers, vertex references that are 0 or out
// of range, faces with fewer than 3 corners, files without faces, and degenerate triangles:
// twice the area |(b-a) x (c-a)| <= 1e-12 L^2 with L the longest side, i.e. corners that are
// collinear or coincide up to rounding (after merging, a triangle that uses one vertex twice).
#pragma once
#include <string>

#include "mesh/triangle_surface.hpp"

namespace dipc {

// Chooses the format from the extension (.obj or .stl, any case); other extensions are a
// MeshError naming the file.
TriangleSurface read_triangle_surface(const std::string& path);

TriangleSurface read_obj(const std::string& path);
TriangleSurface read_stl(const std::string& path);

}  // namespace dipc
