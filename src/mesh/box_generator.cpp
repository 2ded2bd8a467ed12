// Structured box generator (see box_generator.hpp for the numbering it guarantees).
#include "mesh/box_generator.hpp"

#include <cmath>
#include <cstdint>
#include <limits>

#include "mesh/mesh_error.hpp"

namespace dipc {

namespace {

const char* const kAxis = "xyz";

std::string where(const std::string& name) { return "generate_box('" + name + "'): "; }

void validate_box(const std::array<double, 3>& size, const std::array<int, 3>& resolution,
                  const std::array<double, 3>& origin, int body, const std::string& name) {
  if (name.empty()) throw MeshError("generate_box: the box needs a name to prefix its node sets");
  for (int d = 0; d < 3; ++d) {
    if (resolution[d] < 1)
      throw MeshError(where(name) + "resolution along " + kAxis[d] + " is " + std::to_string(resolution[d]) +
                      ", must be >= 1");
    if (!std::isfinite(size[d]) || size[d] <= 0)
      throw MeshError(where(name) + "size along " + kAxis[d] + " is " + std::to_string(size[d]) +
                      ", must be finite and > 0");
    if (!std::isfinite(origin[d])) throw MeshError(where(name) + "origin along " + kAxis[d] + " is not finite");
  }
  if (body < 0) throw MeshError(where(name) + "body id " + std::to_string(body) + " is negative");
  // 8 ids per element must be addressable as int64; check in floating point to avoid overflow.
  const double n = (resolution[0] + 1.0) * (resolution[1] + 1.0) * (resolution[2] + 1.0);
  if (8.0 * n > static_cast<double>(std::numeric_limits<std::int64_t>::max()))
    throw MeshError(where(name) + "resolution is too large (node count overflows 64-bit ids)");
}

}  // namespace

HexMesh generate_box(const std::array<double, 3>& size, const std::array<int, 3>& resolution,
                     const std::array<double, 3>& origin, int body, const std::string& name) {
  validate_box(size, resolution, origin, body, name);
  const std::int64_t nx = resolution[0], ny = resolution[1], nz = resolution[2];
  const std::int64_t px = nx + 1, py = ny + 1, pz = nz + 1;
  auto node_id = [&](std::int64_t i, std::int64_t j, std::int64_t k) { return i + px * (j + py * k); };

  HexMesh mesh;
  mesh.nodes.reserve(static_cast<std::size_t>(px * py * pz));
  for (std::int64_t k = 0; k < pz; ++k)
    for (std::int64_t j = 0; j < py; ++j)
      for (std::int64_t i = 0; i < px; ++i)
        // Position from the index (not by accumulating h) so the last layer lands exactly on
        // origin + size and face-node coordinates compare equal to the face plane.
        mesh.nodes.push_back({origin[0] + size[0] * static_cast<double>(i) / nx,
                              origin[1] + size[1] * static_cast<double>(j) / ny,
                              origin[2] + size[2] * static_cast<double>(k) / nz});

  mesh.hexes.reserve(static_cast<std::size_t>(nx * ny * nz));
  for (std::int64_t k = 0; k < nz; ++k)
    for (std::int64_t j = 0; j < ny; ++j)
      for (std::int64_t i = 0; i < nx; ++i)
        // Gmsh order: bottom face (ζ=-1) counter-clockwise seen from +z, then the top face;
        // with x, y, z along ξ, η, ζ the Jacobian is diag(h/2) > 0.
        mesh.hexes.push_back({node_id(i, j, k), node_id(i + 1, j, k), node_id(i + 1, j + 1, k), node_id(i, j + 1, k),
                              node_id(i, j, k + 1), node_id(i + 1, j, k + 1), node_id(i + 1, j + 1, k + 1),
                              node_id(i, j + 1, k + 1)});
  mesh.body.assign(mesh.hexes.size(), body);

  // Node ids grow with i fastest, then j, then k, so iterating in id order keeps every set
  // sorted as HexMesh requires.
  auto& all = mesh.node_sets[name];
  auto& xmin = mesh.node_sets[name + ".xmin"];
  auto& xmax = mesh.node_sets[name + ".xmax"];
  auto& ymin = mesh.node_sets[name + ".ymin"];
  auto& ymax = mesh.node_sets[name + ".ymax"];
  auto& zmin = mesh.node_sets[name + ".zmin"];
  auto& zmax = mesh.node_sets[name + ".zmax"];
  all.reserve(mesh.nodes.size());
  for (std::int64_t k = 0; k < pz; ++k)
    for (std::int64_t j = 0; j < py; ++j)
      for (std::int64_t i = 0; i < px; ++i) {
        const std::int64_t n = node_id(i, j, k);
        all.push_back(n);
        if (i == 0) xmin.push_back(n);
        if (i == nx) xmax.push_back(n);
        if (j == 0) ymin.push_back(n);
        if (j == ny) ymax.push_back(n);
        if (k == 0) zmin.push_back(n);
        if (k == nz) zmax.push_back(n);
      }
  return mesh;
}

}  // namespace dipc
