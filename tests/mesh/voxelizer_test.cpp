// The voxeliser and what it relies on: the closed-surface check (open, non-manifold and
// inconsistently oriented surfaces rejected naming an edge and the faces on it), the
// generalised winding number, inside classification (including grid rows that run exactly
// along surface edges), first-order convergence of the meshed volume to the enclosed volume
// of a sphere and a torus written as OBJ files, and the MSH 4.1 writer read back by read_gmsh.
#include "mesh/voxelizer.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>

#include "mesh/closed_surface.hpp"
#include "mesh/gmsh_reader.hpp"
#include "mesh/gmsh_writer.hpp"
#include "mesh/hex8_reference.hpp"
#include "mesh/mesh_checks.hpp"
#include "mesh/mesh_error.hpp"
#include "mesh/surface_snapping.hpp"
#include "mesh/triangle_surface_reader.hpp"
#include "mesh_test_support.hpp"

namespace dipc {
namespace {

constexpr double kPi = 3.14159265358979323846;

// A parametric surface (u, v) in [0,1)^2 -> R^3 on an nu x nv grid of quads, two triangles
// each, written as OBJ. `pole` closes v = 0 and v = 1 with one vertex each (a sphere);
// otherwise v wraps around (a torus).
std::string write_parametric_obj(const std::string& name, int nu, int nv, bool poles,
                                 const std::function<Vec3(double, double)>& at) {
  const std::string path = ::testing::TempDir() + name;
  std::ofstream out(path);
  out.precision(17);
  const int rings = poles ? nv - 1 : nv;  // rows of vertices besides the poles
  for (int j = 0; j < rings; ++j)
    for (int i = 0; i < nu; ++i) {
      const Vec3 p = at(double(i) / nu, poles ? double(j + 1) / nv : double(j) / nv);
      out << "v " << p[0] << " " << p[1] << " " << p[2] << "\n";
    }
  auto id = [&](int i, int j) { return 1 + (j % rings) * nu + (i % nu); };  // 1-based
  if (poles) {
    const Vec3 n = at(0, 0), s = at(0, 1);
    out << "v " << n[0] << " " << n[1] << " " << n[2] << "\nv " << s[0] << " " << s[1] << " " << s[2] << "\n";
    const int north = rings * nu + 1, south = north + 1;
    for (int i = 0; i < nu; ++i) {
      out << "f " << north << " " << id(i, 0) << " " << id(i + 1, 0) << "\n";
      out << "f " << id(i, rings - 1) << " " << south << " " << id(i + 1, rings - 1) << "\n";
    }
  }
  for (int j = 0; j < (poles ? rings - 1 : rings); ++j)
    for (int i = 0; i < nu; ++i)
      out << "f " << id(i, j) << " " << id(i, j + 1) << " " << id(i + 1, j + 1) << " " << id(i + 1, j) << "\n";
  return path;
}

// Unit-radius sphere, outward (v runs from the north pole down, u eastward).
std::string sphere_obj() {
  return write_parametric_obj("sphere.obj", 96, 48, true, [](double u, double v) {
    const double th = kPi * v, ph = 2 * kPi * u;
    return Vec3{std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th)};
  });
}

// Torus, R = 1, r = 0.4, tilted so that no axis is special.
std::string torus_obj() {
  return write_parametric_obj("torus.obj", 120, 48, false, [](double u, double v) {
    const double a = 2 * kPi * u, b = -2 * kPi * v;
    const Vec3 p{(1 + 0.4 * std::cos(b)) * std::cos(a), (1 + 0.4 * std::cos(b)) * std::sin(a), 0.4 * std::sin(b)};
    const double t = 0.3;  // rotation about x
    return Vec3{p[0], std::cos(t) * p[1] - std::sin(t) * p[2], std::sin(t) * p[1] + std::cos(t) * p[2]};
  });
}

TriangleSurface cube() { return read_obj(test::mesh_data("surfaces/unit_cube_quads.obj")); }

void expect_mesh_error(const std::function<void()>& f, const std::vector<std::string>& parts) {
  try {
    f();
    FAIL() << "no MeshError";
  } catch (const MeshError& e) {
    for (const std::string& p : parts) EXPECT_NE(std::string(e.what()).find(p), std::string::npos) << e.what();
  }
}

TEST(ClosedSurface, AcceptsClosedSurfaces) {
  EXPECT_NO_THROW(check_closed_surface(cube()));
  EXPECT_NO_THROW(check_closed_surface(read_obj(sphere_obj())));
  EXPECT_NO_THROW(check_closed_surface(read_obj(torus_obj())));
  EXPECT_DOUBLE_EQ(signed_enclosed_volume(cube()), 1.0);
}

TEST(ClosedSurface, RejectsAMissingFaceNamingAnEdge) {
  TriangleSurface s = cube();
  s.triangles.pop_back();  // the second triangle of the face on line 30: (4 5 8)
  s.triangle_origin.pop_back();
  const std::string path = s.source;
  expect_mesh_error([&] { check_closed_surface(s); },
                    {path + ": the surface is not closed: edge (", "belongs to one triangle only (" + path + ":",
                     "a solid needs a closed surface"});
}

TEST(ClosedSurface, RejectsNonManifoldAndFlippedFaces) {
  TriangleSurface fin = cube();
  // A fin on the edge (0,0,0)-(1,0,0): three triangles on it.
  fin.vertices.push_back({0.5, -1, 0});
  const std::int64_t a = 0, extra = static_cast<std::int64_t>(fin.vertices.size()) - 1;
  std::int64_t b = -1;
  for (std::size_t v = 0; v < fin.vertices.size(); ++v)
    if (fin.vertices[v] == Vec3{1, 0, 0}) b = static_cast<std::int64_t>(v);
  ASSERT_EQ(fin.vertices[a], (Vec3{0, 0, 0}));
  fin.triangles.push_back({a, b, extra});
  fin.triangle_origin.push_back(99);
  expect_mesh_error([&] { check_closed_surface(fin); },
                    {"the surface is not manifold: edge (0 0 0)-(1 0 0) is shared by 3 triangles",
                     "unit_cube_quads.obj:99"});

  TriangleSurface flipped = cube();
  std::swap(flipped.triangles[4][1], flipped.triangles[4][2]);
  expect_mesh_error([&] { check_closed_surface(flipped); },
                    {"the surface is not consistently oriented", "unit_cube_quads.obj:25"});
}

TEST(WindingNumber, IsOneInsideZeroOutsideHalfOnTheSurface) {
  const TriangleSurface s = cube();
  EXPECT_NEAR(winding_number(s, {0.5, 0.5, 0.5}), 1.0, 1e-12);
  EXPECT_NEAR(winding_number(s, {0.1, 0.9, 0.2}), 1.0, 1e-12);
  EXPECT_NEAR(winding_number(s, {1.5, 0.5, 0.5}), 0.0, 1e-12);
  EXPECT_NEAR(winding_number(s, {-3, 7, 2}), 0.0, 1e-12);
  EXPECT_NEAR(winding_number(s, {0.5, 0.5, 1.0}), 0.5, 1e-12);  // on the top face
  TriangleSurface inward = s;
  for (Triangle& t : inward.triangles) std::swap(t[1], t[2]);
  EXPECT_NEAR(winding_number(inward, {0.5, 0.5, 0.5}), -1.0, 1e-12);
}

// The cube at resolution 4: cell centres 1/8 from the faces, never on them, but the x-rows
// with y = z run along the diagonals of the faces x = 0 and x = 1, so the tie-break passes
// (rays along y and z, then the solid-angle sum) must decide them. Every cell is inside.
TEST(Voxelizer, RowsAlongSurfaceEdgesAreDecidedCorrectly) {
  const TriangleSurface s = cube();
  VoxelGrid grid;
  VoxelClassification c;
  const HexMesh mesh = voxelize(s, 4, 0, &grid, &c);
  EXPECT_EQ(grid.cells, (std::array<std::int64_t, 3>{4, 4, 4}));
  EXPECT_EQ(grid.h, 0.25);
  EXPECT_EQ(mesh.hexes.size(), 64u);
  EXPECT_EQ(mesh.nodes.size(), 125u);
  EXPECT_GT(c.solid_angle_cells, 0) << "no cell needed the fallback: the test lost its point";
  EXPECT_NEAR(test::mesh_volume(mesh), 1.0, 1e-14);
  // By cell size: ceil(1 / 0.3) = 4 cells per axis, the grid overhanging the cube by 0.1 on
  // each side, so every centre (0.05, 0.35, 0.65, 0.95) is inside.
  const HexMesh by_size = voxelize(s, 0, 0.3, &grid);
  EXPECT_EQ(grid.cells, (std::array<std::int64_t, 3>{4, 4, 4}));
  EXPECT_NEAR(grid.origin[0], -0.1, 1e-15);
  EXPECT_EQ(by_size.hexes.size(), 64u);
}

// The octahedron |x| + |y| + |z| <= 1 at odd resolutions: grid rows run through its vertices
// and along its edges (y = 0, z = 0, ...), and many centres lie on its faces. Every cell whose
// centre is clearly inside or outside must be classified as the exact test says.
TEST(Voxelizer, RowsThroughVerticesMatchTheExactInsideTest) {
  const std::string path = ::testing::TempDir() + "octahedron.obj";
  std::ofstream(path) << "v 1 0 0\nv -1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nv 0 0 -1\n"
                         "f 1 3 5\nf 3 2 5\nf 2 4 5\nf 4 1 5\nf 3 1 6\nf 2 3 6\nf 4 2 6\nf 1 4 6\n";
  const TriangleSurface s = read_obj(path);
  EXPECT_DOUBLE_EQ(signed_enclosed_volume(s), 4.0 / 3);
  for (int n : {3, 9, 15}) {
    SCOPED_TRACE(n);
    VoxelGrid grid = make_voxel_grid(s, n, 0);
    const VoxelClassification c = classify_cells(s, grid);
    int checked = 0;
    for (std::int64_t k = 0; k < n; ++k)
      for (std::int64_t j = 0; j < n; ++j)
        for (std::int64_t i = 0; i < n; ++i) {
          const Vec3 p = grid.centre(i, j, k);
          const double level = std::abs(p[0]) + std::abs(p[1]) + std::abs(p[2]) - 1;
          if (std::abs(level) < 1e-9) continue;  // on a face: either answer is right
          ++checked;
          EXPECT_EQ(bool(c.inside[grid.cell_index(i, j, k)]), level < 0) << i << " " << j << " " << k;
        }
    EXPECT_GT(checked, n * n * n / 2);
    EXPECT_GT(c.solid_angle_cells, 0);
  }
  EXPECT_EQ(voxelize(s, 3, 0).hexes.size(), 7u);  // the centre cell and its 6 face neighbours
}

// Meshed volume against the volume the triangle surface encloses, as the resolution
// doubles. Centre sampling misclassifies only cells cut by the surface, so
// |V_h - V| <= (cells cut) h^3 ~ C A h: first order, sometimes better where errors cancel.
void expect_first_order(const std::string& path, const char* what) {
  const TriangleSurface s = read_obj(path);
  const double exact = signed_enclosed_volume(s);
  double area = 0;
  for (const Triangle& t : s.triangles) {
    const Vec3 &a = s.vertices[t[0]], &b = s.vertices[t[1]], &c = s.vertices[t[2]];
    const Vec3 u{b[0] - a[0], b[1] - a[1], b[2] - a[2]}, v{c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    area += 0.5 * std::sqrt(std::pow(u[1] * v[2] - u[2] * v[1], 2) + std::pow(u[2] * v[0] - u[0] * v[2], 2) +
                            std::pow(u[0] * v[1] - u[1] * v[0], 2));
  }
  std::vector<double> h, error;
  for (int n : {8, 16, 32, 64}) {
    VoxelGrid grid;
    const HexMesh mesh = voxelize(s, n, 0, &grid);
    const double volume = test::mesh_volume(mesh);
    EXPECT_NEAR(volume, double(mesh.hexes.size()) * std::pow(grid.h, 3), 1e-12 * volume);
    h.push_back(grid.h);
    error.push_back(std::abs(volume - exact));
    std::printf("%s n = %2d: h = %.4f, volume %.6f (exact %.6f), error %.3e, error / (A h) %.3f\n", what, n, grid.h,
                volume, exact, error.back(), error.back() / (area * grid.h));
    // Cells cut by the surface lie within sqrt(3) h / 2 of it, a shell of volume ~ sqrt(3) A h.
    EXPECT_LE(error.back(), std::sqrt(3.0) * area * grid.h) << what << " n = " << n;
  }
  // Least-squares slope of log error against log h over the four resolutions.
  double mx = 0, my = 0;
  for (std::size_t i = 0; i < h.size(); ++i) mx += std::log(h[i]) / 4, my += std::log(error[i]) / 4;
  double sxy = 0, sxx = 0;
  for (std::size_t i = 0; i < h.size(); ++i) {
    sxy += (std::log(h[i]) - mx) * (std::log(error[i]) - my);
    sxx += std::pow(std::log(h[i]) - mx, 2);
  }
  std::printf("%s: observed order %.2f\n", what, sxy / sxx);
  EXPECT_GE(sxy / sxx, 0.9) << what;
  EXPECT_LT(error.back(), error.front() / 4) << what;
}

TEST(Voxelizer, VolumeConvergesAtFirstOrderOnASphere) { expect_first_order(sphere_obj(), "sphere"); }
TEST(Voxelizer, VolumeConvergesAtFirstOrderOnATorus) { expect_first_order(torus_obj(), "torus"); }

TEST(Voxelizer, InwardFacingSurfaceGivesTheSameMesh) {
  TriangleSurface s = read_obj(torus_obj());
  const HexMesh outward = voxelize(s, 24, 0);
  for (Triangle& t : s.triangles) std::swap(t[1], t[2]);
  const HexMesh inward = voxelize(s, 24, 0);
  EXPECT_EQ(inward.hexes, outward.hexes);
  EXPECT_GT(outward.hexes.size(), 100u);
}

TEST(Voxelizer, RejectsOpenSurfacesAndTooCoarseGrids) {
  const std::string open = ::testing::TempDir() + "open_box.obj";
  std::ofstream(open) << "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
                         "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\n";  // no x = 0 face
  expect_mesh_error([&] { voxelize(read_obj(open), 8, 0); },
                    {open + ": the surface is not closed: edge", "belongs to one triangle only"});
  // One cell along the longest side: its centre is the torus's, in the hole.
  expect_mesh_error([&] { voxelize(read_obj(torus_obj()), 1, 0); },
                    {"torus.obj: no cell centre of the 1 x 1 x 1 grid", "use a finer resolution"});
}

TEST(GmshWriter, VoxelMeshReadsBackWithItsGroups) {
  const HexMesh mesh = voxelize(read_obj(torus_obj()), 12, 0);
  QuadGroup top{"top", {}}, all{"everything", {}};
  top.quads.push_back({mesh.hexes[0][4], mesh.hexes[0][5], mesh.hexes[0][6], mesh.hexes[0][7]});
  for (const Hex& h : mesh.hexes) all.quads.push_back({h[0], h[3], h[2], h[1]});
  const std::string path = ::testing::TempDir() + "voxel_torus.msh";
  write_gmsh(path, mesh, "solid", {top, all});
  const HexMesh back = read_gmsh(path, 0);
  EXPECT_EQ(back.nodes, mesh.nodes);  // 17 digits: bit for bit
  EXPECT_EQ(back.hexes, mesh.hexes);
  std::vector<std::int64_t> every(mesh.nodes.size());
  for (std::size_t i = 0; i < every.size(); ++i) every[i] = static_cast<std::int64_t>(i);
  EXPECT_EQ(back.node_sets.at("solid"), every);
  std::vector<std::int64_t> top_nodes(mesh.hexes[0].begin() + 4, mesh.hexes[0].end());
  std::sort(top_nodes.begin(), top_nodes.end());
  EXPECT_EQ(back.node_sets.at("top"), top_nodes);
  std::vector<std::int64_t> bottoms;
  for (const Hex& h : mesh.hexes) bottoms.insert(bottoms.end(), h.begin(), h.begin() + 4);
  std::sort(bottoms.begin(), bottoms.end());
  bottoms.erase(std::unique(bottoms.begin(), bottoms.end()), bottoms.end());
  EXPECT_EQ(back.node_sets.at("everything"), bottoms);
}

// Snapping the sphere's voxel mesh: every element keeps min det J >= 0.1 h^3/8 at its corners
// and Gauss points (checked here independently), the nodes reported as snapped lie on the
// triangle surface (within the polygon's deviation from the unit sphere, 1 - cos(pi/48) at
// the equator's edge midpoints), some moves had to be backed off, and the meshed volume stays
// within the first-order bound.
TEST(SurfaceSnapping, KeepsElementsValidAndMovesNodesOntoTheSurface) {
  const TriangleSurface s = read_obj(sphere_obj());
  for (int n : {16, 32}) {
    SCOPED_TRACE(n);
    VoxelGrid grid;
    HexMesh mesh = voxelize(s, n, 0, &grid);
    const HexMesh staircase = mesh;
    const SnapStatistics stats = snap_to_surface(mesh, s, grid.h, 0.1);
    EXPECT_EQ(stats.moved + stats.backed_off + stats.not_moved, stats.boundary_nodes);
    EXPECT_GT(stats.moved, stats.boundary_nodes / 3);
    EXPECT_GT(stats.backed_off, 0) << "nothing was backed off: the check went untested";
    const double cube = std::pow(grid.h, 3) / 8;
    double worst = 1e300;
    for (std::size_t e = 0; e < mesh.hexes.size(); ++e) {
      double X[24];
      test::element_coordinates(mesh, e, X);
      worst = std::min(worst, hex8::min_jacobian_determinant(X));
    }
    EXPECT_GE(worst, 0.1 * cube);
    EXPECT_NEAR(worst / cube, stats.min_det_ratio, 1e-12);
    EXPECT_NO_THROW(check_mesh(mesh, "snapped sphere"));
    // Counted over all nodes: a grid node already on the surface (the poles) is "moved" by 0.
    std::int64_t on_surface = 0, changed = 0;
    for (std::size_t v = 0; v < mesh.nodes.size(); ++v) {
      const Vec3& p = mesh.nodes[v];
      if (std::abs(std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]) - 1) <= 1 - std::cos(kPi / 48) + 1e-12)
        ++on_surface;
      if (p != staircase.nodes[v]) ++changed;
    }
    EXPECT_LE(changed, stats.moved + stats.backed_off);
    EXPECT_GE(changed, stats.backed_off);
    EXPECT_GE(on_surface, stats.moved);
    const double area = 4 * kPi;  // the sphere's, to within the first-order bound's slack
    EXPECT_LE(std::abs(test::mesh_volume(mesh) - signed_enclosed_volume(s)), std::sqrt(3.0) * area * grid.h);
  }
}

}  // namespace
}  // namespace dipc
