#include "app/scene_mesh.hpp"

#include "mesh/box_generator.hpp"
#include "mesh/gmsh_reader.hpp"
#include "mesh/mesh_checks.hpp"
#include "mesh/nested_bodies.hpp"

namespace dipc {

HexMesh build_scene_mesh(const Scene& scene) {
  HexMesh all;
  for (std::size_t b = 0; b < scene.bodies.size(); ++b) {
    const Body& body = scene.bodies[b];
    const int id = static_cast<int>(b);
    if (body.box) {
      all.append(generate_box(body.box->size, body.box->resolution, body.box->origin, id, body.name));
      continue;
    }
    HexMesh part = read_gmsh(body.mesh_file, id);
    for (Vec3& X : part.nodes)
      for (int c = 0; c < 3; ++c) X[c] = body.scale * X[c] + body.translation[c];
    HexMesh named;
    named.nodes = std::move(part.nodes);
    named.hexes = std::move(part.hexes);
    named.body = std::move(part.body);
    for (auto& [name, nodes] : part.node_sets) named.node_sets[body.name + "." + name] = std::move(nodes);
    std::vector<std::int64_t> every(named.nodes.size());
    for (std::size_t i = 0; i < every.size(); ++i) every[i] = static_cast<std::int64_t>(i);
    named.node_sets[body.name] = std::move(every);
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
