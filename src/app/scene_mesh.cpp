#include "app/scene_mesh.hpp"

#include <algorithm>
#include <set>

#include "mesh/boundary_faces.hpp"
#include "mesh/box_generator.hpp"
#include "mesh/gmsh_reader.hpp"
#include "mesh/mesh_checks.hpp"
#include "mesh/mesh_error.hpp"
#include "mesh/nested_bodies.hpp"

namespace dipc {

namespace {

// PolyFEM's surface selections (Body::face_selections) as node sets of `part` (one body):
// each boundary face takes the id of the first selection holding its centroid (the mean of
// its 4 corners), and "<body>.surface_selection_<id>" collects the nodes of the faces with
// that id. Every id the body declares gets a set, empty when no face took it; the Dirichlet
// check then reports a condition that selects no node.
void add_face_selection_sets(const Body& body, const std::string& source, HexMesh& part) {
  if (body.face_selections.empty()) return;
  std::map<int, std::set<std::int64_t>> nodes_of_id;
  for (const FaceSelection& s : body.face_selections) nodes_of_id[s.id];
  for (const BoundaryFace& f : extract_boundary_faces(part)) {
    const std::array<int, 4> local = hex_face_nodes(f.face);
    Vec3 centroid{0, 0, 0};
    for (int k : local)
      for (int c = 0; c < 3; ++c) centroid[c] += 0.25 * part.nodes[part.hexes[f.element][k]][c];
    for (const FaceSelection& s : body.face_selections) {
      bool inside = true;
      if (s.box)
        for (int c = 0; c < 3; ++c) inside = inside && centroid[c] >= (*s.box)[c] && centroid[c] <= (*s.box)[3 + c];
      if (!inside) continue;
      for (int k : local) nodes_of_id[s.id].insert(part.hexes[f.element][k]);
      break;
    }
  }
  for (const auto& [id, nodes] : nodes_of_id) {
    const std::string name = body.name + ".surface_selection_" + std::to_string(id);
    if (part.node_sets.count(name))
      throw MeshError(source + ": body \"" + body.name + "\": its mesh already has a selection named \"" + name + "\"");
    part.node_sets[name] = std::vector<std::int64_t>(nodes.begin(), nodes.end());
  }
}

}  // namespace

HexMesh build_scene_mesh(const Scene& scene) {
  HexMesh all;
  for (std::size_t b = 0; b < scene.bodies.size(); ++b) {
    const Body& body = scene.bodies[b];
    const int id = static_cast<int>(b);
    if (body.box) {
      HexMesh part = generate_box(body.box->size, body.box->resolution, body.box->origin, id, body.name);
      add_face_selection_sets(body, scene.source, part);
      all.append(part);
      continue;
    }
    HexMesh part = read_gmsh(body.mesh_file, id);
    const std::array<double, 9>& L = body.linear;
    for (Vec3& X : part.nodes) {
      const Vec3 Y = X;
      for (int c = 0; c < 3; ++c)
        X[c] = body.scale * (L[3 * c] * Y[0] + L[3 * c + 1] * Y[1] + L[3 * c + 2] * Y[2]) + body.translation[c];
    }
    HexMesh named;
    named.nodes = std::move(part.nodes);
    named.hexes = std::move(part.hexes);
    named.body = std::move(part.body);
    for (auto& [name, nodes] : part.node_sets) named.node_sets[body.name + "." + name] = std::move(nodes);
    std::vector<std::int64_t> every(named.nodes.size());
    for (std::size_t i = 0; i < every.size(); ++i) every[i] = static_cast<std::int64_t>(i);
    named.node_sets[body.name] = std::move(every);
    add_face_selection_sets(body, scene.source, named);
    all.append(named);
  }
  check_mesh(all, scene.source);
  // Without contact bodies pass through each other, so one inside another is no error there.
  if (scene.contact.enabled) {
    std::vector<std::string> names;
    for (const Body& body : scene.bodies) names.push_back(body.name);
    check_no_nested_bodies(all, names, scene.source);
  }
  return all;
}

}  // namespace dipc
