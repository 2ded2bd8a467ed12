// Voxeliser: a hexahedral mesh of the solid bounded by a closed triangle surface, made of the
// cells of a regular grid whose centres lie inside the surface.
//
// Inside means generalised winding number w(p) > 1/2 (Jacobson, Kavan, Sorkine-Hornung 2013,
// "Robust inside-outside segmentation using generalized winding numbers"): w(p) = Σ Ω_t(p)/4π
// over the triangles, Ω_t the signed solid angle of triangle t seen from p. For a closed,
// consistently oriented surface w is the integer number of times the surface winds around p,
// which also equals the signed number of crossings of any ray from p (+1 where the ray leaves
// through a triangle, -1 where it enters). The grid is classified row by row with that ray
// count (O(triangles x rows they cover + cells), not O(cells x triangles)): along x, then
// along y and z for cells that an x-row could not decide, and by the solid-angle sum for the
// rest. A row cannot decide where it passes within a tolerance (1e-9 of the bounding box
// diagonal) of a triangle edge or vertex in projection, nor a cell whose centre lies within
// it of a crossing: there the count could depend on rounding, while the solid-angle sum is
// continuous in p (near the surface it is near 1/2 and either answer is right).
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "mesh/hex_mesh.hpp"
#include "mesh/triangle_surface.hpp"

namespace dipc {

struct VoxelGrid {
  Vec3 origin{0, 0, 0};  // lowest corner of cell (0, 0, 0)
  double h = 0;          // cell edge length
  std::array<std::int64_t, 3> cells{0, 0, 0};
  std::int64_t cell_index(std::int64_t i, std::int64_t j, std::int64_t k) const {
    return i + cells[0] * (j + cells[1] * k);
  }
  Vec3 centre(std::int64_t i, std::int64_t j, std::int64_t k) const {
    return {origin[0] + (i + 0.5) * h, origin[1] + (j + 0.5) * h, origin[2] + (k + 0.5) * h};
  }
};

// The grid over the surface's bounding box with `resolution` cells along its longest side, or
// cells of edge `cell_size` (exactly one of the two > 0): ceil(side / h) cells per axis (at
// least 1), centred on the box. Throws MeshError for a flat bounding box or a grid of more
// than 2^31 cells.
VoxelGrid make_voxel_grid(const TriangleSurface& surface, std::int64_t resolution, double cell_size);

// w(p) by the solid-angle sum, each Ω_t from van Oosterom & Strackee (1983):
// tan(Ω/2) = a·(b×c) / (|a||b||c| + (a·b)|c| + (b·c)|a| + (c·a)|b|), a, b, c the corners
// relative to p.
double winding_number(const TriangleSurface& surface, const Vec3& p);

struct VoxelClassification {
  std::vector<char> inside;            // per cell, VoxelGrid::cell_index order
  std::int64_t solid_angle_cells = 0;  // cells no ray row could decide
};

// Inside flags of every cell centre. `surface` must be closed and consistently oriented
// (check_closed_surface), facing either way: the sign of its enclosed volume is taken into
// account.
VoxelClassification classify_cells(const TriangleSurface& surface, const VoxelGrid& grid);

// The hexahedra of the inside cells (body 0), on the grid's nodes that they use, numbered
// with x fastest, then y, then z; node sets: none.
HexMesh voxel_mesh(const VoxelGrid& grid, const std::vector<char>& inside);

// check_closed_surface, make_voxel_grid, classify_cells and voxel_mesh; throws MeshError
// naming the surface file when no cell centre is inside (resolution too coarse).
HexMesh voxelize(const TriangleSurface& surface, std::int64_t resolution, double cell_size,
                 VoxelGrid* grid_out = nullptr, VoxelClassification* classification_out = nullptr);

}  // namespace dipc
