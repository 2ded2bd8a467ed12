// Voxeliser (see voxelizer.hpp).
#include "mesh/voxelizer.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <tuple>

#include "math/vector3.hpp"
#include "mesh/closed_surface.hpp"
#include "mesh/mesh_error.hpp"

namespace dipc {

namespace {

constexpr double kPi = 3.14159265358979323846;

void bounding_box(const TriangleSurface& s, Vec3& lo, Vec3& hi) {
  lo = hi = s.vertices.at(0);
  for (const Vec3& p : s.vertices)
    for (int d = 0; d < 3; ++d) {
      lo[d] = std::min(lo[d], p[d]);
      hi[d] = std::max(hi[d], p[d]);
    }
}

// Edge function of the projected edge P -> Q at p in the plane of axes (b, c): twice the
// signed area of (P, Q, p). Evaluated with the end points in a fixed order, so that the two
// triangles on an edge (which run along it in opposite directions) get exactly opposite values.
double edge_function(const Vec3& P, const Vec3& Q, double pb, double pc, int b, int c) {
  const bool swap = std::tie(Q[b], Q[c]) < std::tie(P[b], P[c]);
  const Vec3& A = swap ? Q : P;
  const Vec3& B = swap ? P : Q;
  const double e = (B[b] - A[b]) * (pc - A[c]) - (B[c] - A[c]) * (pb - A[b]);
  return swap ? -e : e;
}

struct Crossing {
  double x;
  int sign;  // +1: the +x ray leaves through the triangle there, -1: it enters
  bool operator<(const Crossing& o) const { return x < o.x; }
};

}  // namespace

VoxelGrid make_voxel_grid(const TriangleSurface& surface, std::int64_t resolution, double cell_size) {
  if ((resolution > 0) == (cell_size > 0))
    throw MeshError(surface.source + ": give either a resolution or a cell size");
  Vec3 lo, hi;
  bounding_box(surface, lo, hi);
  const double longest = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
  for (int d = 0; d < 3; ++d)
    if (!(hi[d] - lo[d] > 1e-12 * longest))
      throw MeshError(surface.source + ": the surface is flat (its bounding box has no extent in " + "xyz"[d] + ")");
  VoxelGrid grid;
  grid.h = resolution > 0 ? longest / static_cast<double>(resolution) : cell_size;
  double total = 1;
  for (int d = 0; d < 3; ++d) {
    // A side that is a whole number of cells up to rounding gets exactly that many.
    const double n = std::ceil((hi[d] - lo[d]) / grid.h * (1 - 1e-12));
    grid.cells[d] = std::max<std::int64_t>(1, static_cast<std::int64_t>(n));
    total *= static_cast<double>(grid.cells[d]);
    grid.origin[d] = 0.5 * (lo[d] + hi[d]) - 0.5 * static_cast<double>(grid.cells[d]) * grid.h;
  }
  if (total > 2147483648.0) {
    std::ostringstream msg;
    msg << surface.source << ": a grid of " << grid.cells[0] << " x " << grid.cells[1] << " x " << grid.cells[2]
        << " cells is too large";
    throw MeshError(msg.str());
  }
  return grid;
}

double winding_number(const TriangleSurface& surface, const Vec3& p) {
  double sum = 0;
  for (const Triangle& t : surface.triangles) {
    Vec3 v[3];
    for (int k = 0; k < 3; ++k) subtract3(surface.vertices[t[k]].data(), p.data(), v[k].data());
    sum += solid_angle3(v[0].data(), v[1].data(), v[2].data());
  }
  return sum / (4 * kPi);
}

namespace {

// One pass of ray counting along axis a, for the cells not decided yet: for each grid row
// along a that holds such a cell, the signed crossings of the line with the triangles; a
// cell centre's winding number is the sum of the signs beyond it. Rows that pass within
// `tol` of a projected edge or vertex, or whose signs do not sum to zero, and cells within
// `tol` of a crossing, stay undecided.
void ray_pass(const TriangleSurface& surface, const VoxelGrid& grid, int a, double tol, int orientation,
              std::vector<char>& decided, std::vector<char>& inside) {
  const int b = (a + 1) % 3, c = (a + 2) % 3;  // cyclic, so n_a = ((B-A) x (C-A))_a below
  const std::int64_t na = grid.cells[a], nb = grid.cells[b], nc = grid.cells[c];
  auto cell = [&](std::int64_t ia, std::int64_t ib, std::int64_t ic) {
    std::int64_t idx[3];
    idx[a] = ia, idx[b] = ib, idx[c] = ic;
    return static_cast<std::size_t>(grid.cell_index(idx[0], idx[1], idx[2]));
  };
  std::vector<char> needed(static_cast<std::size_t>(nb * nc), 0);
  bool any = false;
  for (std::int64_t ic = 0; ic < nc; ++ic)
    for (std::int64_t ib = 0; ib < nb; ++ib)
      for (std::int64_t ia = 0; ia < na && !needed[ib + nb * ic]; ++ia)
        if (!decided[cell(ia, ib, ic)]) needed[ib + nb * ic] = any = true;
  if (!any) return;

  std::vector<std::vector<Crossing>> rows(needed.size());
  std::vector<char> row_ambiguous(needed.size(), 0);
  const auto first = [&](double v, int d) {
    return std::max<std::int64_t>(0, static_cast<std::int64_t>(std::ceil((v - grid.origin[d]) / grid.h - 0.5)));
  };
  const auto last = [&](double v, int d) {
    return std::min<std::int64_t>(grid.cells[d] - 1,
                                  static_cast<std::int64_t>(std::floor((v - grid.origin[d]) / grid.h - 0.5)));
  };
  for (const Triangle& t : surface.triangles) {
    const Vec3& A = surface.vertices[t[0]];
    const Vec3& B = surface.vertices[t[1]];
    const Vec3& C = surface.vertices[t[2]];
    // Twice the signed area of the triangle projected on (b, c).
    const double area = edge_function(A, B, C[b], C[c], b, c);
    if (area == 0) continue;  // edge-on: its projection has no interior
    const int sign = area > 0 ? 1 : -1;
    // Rows whose (b, c) lies in the projected bounding box, widened by the tolerance.
    const std::int64_t b0 = first(std::min({A[b], B[b], C[b]}) - tol, b);
    const std::int64_t b1 = last(std::max({A[b], B[b], C[b]}) + tol, b);
    const std::int64_t c0 = first(std::min({A[c], B[c], C[c]}) - tol, c);
    const std::int64_t c1 = last(std::max({A[c], B[c], C[c]}) + tol, c);
    // Edge lengths in projection, to turn edge functions into distances.
    const double lab = std::hypot(B[b] - A[b], B[c] - A[c]);
    const double lbc = std::hypot(C[b] - B[b], C[c] - B[c]);
    const double lca = std::hypot(A[b] - C[b], A[c] - C[c]);
    for (std::int64_t ic = c0; ic <= c1; ++ic)
      for (std::int64_t ib = b0; ib <= b1; ++ib) {
        const std::size_t row = static_cast<std::size_t>(ib + nb * ic);
        if (!needed[row] || row_ambiguous[row]) continue;
        const double pb = grid.origin[b] + (static_cast<double>(ib) + 0.5) * grid.h;
        const double pc = grid.origin[c] + (static_cast<double>(ic) + 0.5) * grid.h;
        // Barycentric weights (times the area) of p for A, B, C; signed distances to the
        // opposite edges, positive inside.
        const double wa = edge_function(B, C, pb, pc, b, c);
        const double wb = edge_function(C, A, pb, pc, b, c);
        const double wc = edge_function(A, B, pb, pc, b, c);
        const double da = sign * wa / lbc, db = sign * wb / lca, dc = sign * wc / lab;
        if (da < -tol || db < -tol || dc < -tol) continue;  // clearly outside
        if (da <= tol || db <= tol || dc <= tol) {
          row_ambiguous[row] = 1;  // on an edge or a vertex up to rounding
          continue;
        }
        const double x = (wa * A[a] + wb * B[a] + wc * C[a]) / (wa + wb + wc);
        rows[row].push_back({x, sign * orientation});
      }
  }

  for (std::int64_t ic = 0; ic < nc; ++ic)
    for (std::int64_t ib = 0; ib < nb; ++ib) {
      const std::size_t row = static_cast<std::size_t>(ib + nb * ic);
      if (!needed[row] || row_ambiguous[row]) continue;
      std::vector<Crossing>& crossings = rows[row];
      std::sort(crossings.begin(), crossings.end());
      int total = 0;
      for (const Crossing& x : crossings) total += x.sign;
      if (total != 0) continue;  // a closed surface is left as often as entered along a line
      // w(p) = Σ signs of the crossings beyond p = -(Σ signs of those before p).
      int before = 0;
      std::size_t next = 0;
      for (std::int64_t ia = 0; ia < na; ++ia) {
        const double p = grid.origin[a] + (static_cast<double>(ia) + 0.5) * grid.h;
        while (next < crossings.size() && crossings[next].x < p) before += crossings[next++].sign;
        const std::size_t k = cell(ia, ib, ic);
        if (decided[k]) continue;
        const bool near_crossing = (next < crossings.size() && crossings[next].x - p <= tol) ||
                                   (next > 0 && p - crossings[next - 1].x <= tol);
        if (near_crossing) continue;
        inside[k] = -before >= 1;
        decided[k] = 1;
      }
    }
}

}  // namespace

VoxelClassification classify_cells(const TriangleSurface& surface, const VoxelGrid& grid) {
  Vec3 lo, hi;
  bounding_box(surface, lo, hi);
  const double diagonal = std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                                    (hi[2] - lo[2]) * (hi[2] - lo[2]));
  // Closer than this to a projected edge, or to a crossing along the row, the ray count is
  // not trusted. Far above the rounding of the edge functions (~1e-16 of the model size).
  const double tol = 1e-9 * diagonal;
  // Winding numbers are counted for outward-facing triangles; an inward-facing surface
  // counts -1 inside.
  const int orientation = signed_enclosed_volume(surface) >= 0 ? 1 : -1;

  const std::size_t n = static_cast<std::size_t>(grid.cells[0] * grid.cells[1] * grid.cells[2]);
  VoxelClassification out;
  out.inside.assign(n, 0);
  std::vector<char> decided(n, 0);
  // Rays along x, then, for cells that no x-row could decide, along y and z (a surface
  // aligned with the grid, a cube say, puts whole x-rows on its edges), then the solid-angle
  // sum for what is left.
  for (int axis = 0; axis < 3; ++axis) ray_pass(surface, grid, axis, tol, orientation, decided, out.inside);
  for (std::int64_t k = 0; k < grid.cells[2]; ++k)
    for (std::int64_t j = 0; j < grid.cells[1]; ++j)
      for (std::int64_t i = 0; i < grid.cells[0]; ++i) {
        const std::size_t idx = static_cast<std::size_t>(grid.cell_index(i, j, k));
        if (decided[idx]) continue;
        out.inside[idx] = orientation * winding_number(surface, grid.centre(i, j, k)) > 0.5;
        ++out.solid_angle_cells;
      }
  return out;
}

HexMesh voxel_mesh(const VoxelGrid& grid, const std::vector<char>& inside) {
  const std::int64_t nx = grid.cells[0], ny = grid.cells[1], nz = grid.cells[2];
  const std::int64_t px = nx + 1, py = ny + 1;
  std::vector<std::int64_t> id(static_cast<std::size_t>(px * py * (nz + 1)), -1);
  auto node = [&](std::int64_t i, std::int64_t j, std::int64_t k) -> std::int64_t& {
    return id[static_cast<std::size_t>(i + px * (j + py * k))];
  };
  // Mark used grid points, then number them in x-fastest order.
  for (std::int64_t k = 0; k < nz; ++k)
    for (std::int64_t j = 0; j < ny; ++j)
      for (std::int64_t i = 0; i < nx; ++i)
        if (inside[static_cast<std::size_t>(grid.cell_index(i, j, k))])
          for (int c = 0; c < 8; ++c) node(i + (c & 1), j + ((c >> 1) & 1), k + (c >> 2)) = 0;
  HexMesh mesh;
  const auto cells = static_cast<std::size_t>(std::count(inside.begin(), inside.end(), 1));
  mesh.hexes.reserve(cells);
  mesh.nodes.reserve(cells + cells / 4);
  for (std::int64_t k = 0; k <= nz; ++k)
    for (std::int64_t j = 0; j <= ny; ++j)
      for (std::int64_t i = 0; i <= nx; ++i)
        if (node(i, j, k) == 0) {
          node(i, j, k) = static_cast<std::int64_t>(mesh.nodes.size());
          mesh.nodes.push_back({grid.origin[0] + static_cast<double>(i) * grid.h,
                                grid.origin[1] + static_cast<double>(j) * grid.h,
                                grid.origin[2] + static_cast<double>(k) * grid.h});
        }
  for (std::int64_t k = 0; k < nz; ++k)
    for (std::int64_t j = 0; j < ny; ++j)
      for (std::int64_t i = 0; i < nx; ++i)
        if (inside[static_cast<std::size_t>(grid.cell_index(i, j, k))])
          // Gmsh/VTK order (hex_mesh.hpp): the bottom face counter-clockwise, then the top.
          mesh.hexes.push_back({node(i, j, k), node(i + 1, j, k), node(i + 1, j + 1, k), node(i, j + 1, k),
                                node(i, j, k + 1), node(i + 1, j, k + 1), node(i + 1, j + 1, k + 1),
                                node(i, j + 1, k + 1)});
  mesh.body.assign(mesh.hexes.size(), 0);
  return mesh;
}

HexMesh voxelize(const TriangleSurface& surface, std::int64_t resolution, double cell_size, VoxelGrid* grid_out,
                 VoxelClassification* classification_out) {
  check_closed_surface(surface);
  const VoxelGrid grid = make_voxel_grid(surface, resolution, cell_size);
  VoxelClassification classification = classify_cells(surface, grid);
  HexMesh mesh = voxel_mesh(grid, classification.inside);
  if (mesh.hexes.empty()) {
    std::ostringstream msg;
    msg << surface.source << ": no cell centre of the " << grid.cells[0] << " x " << grid.cells[1] << " x "
        << grid.cells[2] << " grid (cell size " << grid.h << ") is inside the surface: use a finer resolution";
    throw MeshError(msg.str());
  }
  if (grid_out) *grid_out = grid;
  if (classification_out) *classification_out = std::move(classification);
  return mesh;
}

}  // namespace dipc
