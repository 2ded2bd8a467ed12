// dipc-voxelize: a hexahedral mesh (Gmsh MSH 4.1 ASCII) of the solid bounded by a closed OBJ
// or STL surface, for scene files to name as a body's "mesh".
//
//   dipc-voxelize INPUT.obj|stl OUTPUT.msh (--resolution N | --cell-size H)
//                 [--group NAME XMIN YMIN ZMIN XMAX YMAX ZMAX]... [--snap]
//
// The cells of a regular grid whose centres are inside the surface (mesh/voxelizer.hpp) become
// the hexahedra, in the physical volume "solid"; the boundary quads form the physical surface
// "boundary", and each --group the boundary quads whose 4 corners lie in its box (a scene then
// selects "<body>.<NAME>"). --snap moves the boundary nodes onto the surface where every
// element keeps min det J >= 0.1 h^3/8 (mesh/surface_snapping.hpp). Exit status 1 with
// "dipc-voxelize: error: ..." for bad arguments or input (an open surface names an edge of it).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <vector>

#include "math/small_matrix.hpp"
#include "mesh/boundary_faces.hpp"
#include "mesh/closed_surface.hpp"
#include "mesh/gmsh_writer.hpp"
#include "mesh/hex8_reference.hpp"
#include "mesh/mesh_checks.hpp"
#include "mesh/mesh_error.hpp"
#include "mesh/surface_snapping.hpp"
#include "mesh/triangle_surface_reader.hpp"
#include "mesh/voxelizer.hpp"

namespace {

constexpr const char* kUsage = "usage: dipc-voxelize INPUT.obj|stl OUTPUT.msh (--resolution N | --cell-size H)\n"
                               "                     [--group NAME XMIN YMIN ZMIN XMAX YMAX ZMAX]... [--snap]\n"
                               "  --resolution N  N cells along the longest side of the surface's bounding box\n"
                               "  --cell-size H   cells of edge H\n"
                               "  --group ...     physical surface NAME: the boundary quads inside the box\n"
                               "  --snap          move boundary nodes onto the surface as far as every element keeps\n"
                               "                  det J >= 0.1 h^3/8 at its corners and Gauss points\n";

struct BoxGroup {
  std::string name;
  double lo[3], hi[3];
};

struct Arguments {
  std::string input, output;
  long long resolution = 0;
  double cell_size = 0;
  std::vector<BoxGroup> groups;
  bool snap = false;
};

[[noreturn]] void usage_error(const std::string& what) { throw std::invalid_argument(what + "\n" + kUsage); }

double number(const std::string& text, const std::string& option) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || !std::isfinite(v))
    usage_error(option + ": '" + text + "' is not a finite number");
  return v;
}

Arguments parse(int argc, char** argv) {
  Arguments a;
  std::vector<std::string> positional;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    auto value = [&](const std::string& option) -> std::string {
      if (i + 1 >= argc) usage_error(option + " needs a value");
      return argv[++i];
    };
    if (arg == "--resolution") {
      const std::string v = value(arg);
      char* end = nullptr;
      a.resolution = std::strtoll(v.c_str(), &end, 10);
      if (v.empty() || *end != '\0' || a.resolution < 1 || a.resolution > 100000)
        usage_error("--resolution: '" + v + "' is not an integer in [1, 100000]");
    } else if (arg == "--cell-size") {
      a.cell_size = number(value(arg), arg);
      if (!(a.cell_size > 0)) usage_error("--cell-size must be positive");
    } else if (arg == "--group") {
      if (i + 7 >= argc) usage_error("--group needs a name and 6 numbers");
      BoxGroup g;
      g.name = argv[++i];
      for (int d = 0; d < 3; ++d) g.lo[d] = number(argv[++i], "--group " + g.name);
      for (int d = 0; d < 3; ++d) g.hi[d] = number(argv[++i], "--group " + g.name);
      for (int d = 0; d < 3; ++d)
        if (!(g.lo[d] <= g.hi[d])) usage_error("--group " + g.name + ": min > max in " + "xyz"[d]);
      if (g.name == "boundary" || g.name == "solid")
        usage_error("--group " + g.name + ": the name is taken by the tool's own groups");
      a.groups.push_back(g);
    } else if (arg == "--snap") {
      a.snap = true;
    } else if (arg == "-h" || arg == "--help") {
      std::fputs(kUsage, stdout);
      std::exit(0);
    } else if (!arg.empty() && arg[0] == '-') {
      usage_error("unknown option " + arg);
    } else {
      positional.push_back(arg);
    }
  }
  if (positional.size() != 2) usage_error("expected an input surface and an output .msh file");
  a.input = positional[0];
  a.output = positional[1];
  if ((a.resolution > 0) == (a.cell_size > 0)) usage_error("give exactly one of --resolution and --cell-size");
  return a;
}

int run(const Arguments& a) {
  using namespace dipc;
  const auto start = std::chrono::steady_clock::now();
  const TriangleSurface surface = read_triangle_surface(a.input);
  VoxelGrid grid;
  VoxelClassification classification;
  HexMesh mesh = voxelize(surface, a.resolution, a.cell_size, &grid, &classification);
  // Groups are chosen on the staircase, before snapping, so that a box selects the same
  // faces with or without --snap.

  std::vector<QuadGroup> groups(1 + a.groups.size());
  groups[0].name = "boundary";
  for (std::size_t g = 0; g < a.groups.size(); ++g) groups[g + 1].name = a.groups[g].name;
  for (const BoundaryFace& f : extract_boundary_faces(mesh)) {
    const auto local = hex_face_nodes(f.face);
    std::array<std::int64_t, 4> quad;
    for (int c = 0; c < 4; ++c) quad[c] = mesh.hexes[f.element][local[c]];
    groups[0].quads.push_back(quad);
    for (std::size_t g = 0; g < a.groups.size(); ++g) {
      bool in = true;
      for (std::int64_t v : quad)
        for (int d = 0; d < 3; ++d)
          in = in && mesh.nodes[v][d] >= a.groups[g].lo[d] && mesh.nodes[v][d] <= a.groups[g].hi[d];
      if (in) groups[g + 1].quads.push_back(quad);
    }
  }
  for (std::size_t g = 1; g < groups.size(); ++g)
    if (groups[g].quads.empty())
      throw MeshError("--group " + groups[g].name + ": no boundary face of the mesh lies in its box");
  std::string snapped;
  if (a.snap) {
    const SnapStatistics st = snap_to_surface(mesh, surface, grid.h);
    char line[256];
    std::snprintf(line, sizeof line,
                  "; snapped %lld of %lld boundary nodes, %lld part of the way, %lld not moved, "
                  "min det J %.3f h^3/8",
                  static_cast<long long>(st.moved), static_cast<long long>(st.boundary_nodes),
                  static_cast<long long>(st.backed_off), static_cast<long long>(st.not_moved), st.min_det_ratio);
    snapped = line;
  }
  check_mesh(mesh, a.output);
  write_gmsh(a.output, mesh, "solid", groups);

  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const double cell_volume = grid.h * grid.h * grid.h;
  double meshed = 0;
  if (a.snap) {
    // Exact for trilinear hexes: 2-point Gauss integrates det J (degree <= 2 per axis).
    for (const Hex& e : mesh.hexes) {
      double X[24], dN[24], J[9];
      for (int n = 0; n < 8; ++n)
        for (int i = 0; i < 3; ++i) X[3 * n + i] = mesh.nodes[e[n]][i];
      for (int q = 0; q < hex8::kQuadraturePoints; ++q) {
        double xi, eta, zeta;
        hex8::gauss_point(q, xi, eta, zeta);
        hex8::shape_gradient(xi, eta, zeta, dN);
        hex8::jacobian(X, dN, J);
        meshed += hex8::kGaussWeight * det3x3(J);
      }
    }
  } else {
    meshed = static_cast<double>(mesh.hexes.size()) * cell_volume;
  }
  const double enclosed = std::abs(signed_enclosed_volume(surface));
  std::printf("dipc-voxelize: %s: %zu triangles; grid %lld x %lld x %lld, cell size %.6g; %zu hexahedra, "
              "%zu nodes, %zu boundary quads; volume %.6g (surface encloses %.6g, %+.3f%%); %lld cells "
              "decided by the solid-angle sum%s; %.2f s -> %s\n",
              a.input.c_str(), surface.triangles.size(), static_cast<long long>(grid.cells[0]),
              static_cast<long long>(grid.cells[1]), static_cast<long long>(grid.cells[2]), grid.h, mesh.hexes.size(),
              mesh.nodes.size(), groups[0].quads.size(), meshed, enclosed, 100 * (meshed - enclosed) / enclosed,
              static_cast<long long>(classification.solid_angle_cells), snapped.c_str(), seconds, a.output.c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(parse(argc, argv));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "dipc-voxelize: error: %s\n", e.what());
    return 1;
  }
}
