// Structured hexahedral test meshes built by hand (the partition tests do not link the mesh
// layer): an nx x ny x nz box of unit cubes with face node sets, and the concatenation of two
// meshes into one multi-body mesh.
#pragma once
#include <algorithm>
#include <cstdint>
#include <numeric>
#include <random>
#include <string>

#include "mesh/hex_mesh.hpp"

namespace dipc::test {

// Node (i, j, k) of the box has id i + (nx + 1) * (j + (ny + 1) * k) and coordinates
// origin + (i, j, k); hex corners follow the Gmsh order of hex_mesh.hpp. Node sets
// "<prefix>.xmin", "<prefix>.xmax" and "<prefix>.zmax" hold the nodes on those faces.
inline HexMesh structured_box(int nx, int ny, int nz, Vec3 origin = {0, 0, 0}, int body = 0,
                              const std::string& prefix = "box") {
  HexMesh mesh;
  auto id = [&](int i, int j, int k) { return static_cast<std::int64_t>(i + (nx + 1) * (j + (ny + 1) * k)); };
  for (int k = 0; k <= nz; ++k) {
    for (int j = 0; j <= ny; ++j) {
      for (int i = 0; i <= nx; ++i) {
        mesh.nodes.push_back({origin[0] + i, origin[1] + j, origin[2] + k});
        if (i == 0) mesh.node_sets[prefix + ".xmin"].push_back(id(i, j, k));
        if (i == nx) mesh.node_sets[prefix + ".xmax"].push_back(id(i, j, k));
        if (k == nz) mesh.node_sets[prefix + ".zmax"].push_back(id(i, j, k));
      }
    }
  }
  for (int k = 0; k < nz; ++k) {
    for (int j = 0; j < ny; ++j) {
      for (int i = 0; i < nx; ++i) {
        mesh.hexes.push_back({id(i, j, k), id(i + 1, j, k), id(i + 1, j + 1, k), id(i, j + 1, k), id(i, j, k + 1),
                              id(i + 1, j, k + 1), id(i + 1, j + 1, k + 1), id(i, j + 1, k + 1)});
        mesh.body.push_back(body);
      }
    }
  }
  return mesh;
}

// `a` followed by `b` with b's node ids shifted; node-set names must differ.
inline HexMesh concatenate(HexMesh a, const HexMesh& b) {
  const auto shift = static_cast<std::int64_t>(a.nodes.size());
  a.nodes.insert(a.nodes.end(), b.nodes.begin(), b.nodes.end());
  for (Hex hex : b.hexes) {
    for (std::int64_t& node : hex) node += shift;
    a.hexes.push_back(hex);
  }
  a.body.insert(a.body.end(), b.body.begin(), b.body.end());
  for (const auto& [name, nodes] : b.node_sets) {
    auto& set = a.node_sets[name];
    for (std::int64_t node : nodes) set.push_back(node + shift);
  }
  return a;
}

// Two separate bodies: a 6x4x3 box (body 0) and a 3x2x2 box above it (body 1).
inline HexMesh two_body_mesh() {
  return concatenate(structured_box(6, 4, 3, {0, 0, 0}, 0, "lower"), structured_box(3, 2, 2, {1, 1, 4}, 1, "upper"));
}

// `mesh` with its nodes renumbered as a mesh file may number them: node i gets id
// stride * p(i) for a shuffled permutation p, and the ids in between belong to nodes no element
// touches (at the origin). With a stride of 10 or more the ids of every part are scattered over
// a range much wider than its elements, as distribute_slices' sorting path for node ids needs.
inline HexMesh scattered_node_ids(const HexMesh& mesh, int stride) {
  std::vector<std::int64_t> p(mesh.nodes.size());
  std::iota(p.begin(), p.end(), 0);
  std::shuffle(p.begin(), p.end(), std::mt19937(42));
  for (std::int64_t& id : p) id *= stride;
  HexMesh out;
  out.nodes.assign(mesh.nodes.size() * stride, Vec3{0, 0, 0});
  for (std::size_t i = 0; i < p.size(); ++i) out.nodes[p[i]] = mesh.nodes[i];
  out.hexes = mesh.hexes;
  for (Hex& hex : out.hexes)
    for (std::int64_t& node : hex) node = p[node];
  out.body = mesh.body;
  for (const auto& [name, nodes] : mesh.node_sets) {
    auto& set = out.node_sets[name];
    for (std::int64_t node : nodes) set.push_back(p[node]);
    std::sort(set.begin(), set.end());
  }
  return out;
}

}  // namespace dipc::test
