#include "app/problem_builder.hpp"

#include <cmath>

#include "app/scene_obstacles.hpp"

namespace dipc {

namespace {

std::vector<std::int32_t> select_nodes(const Selection& sel, const DistributedMesh& mesh, double length_scale,
                                       const std::string& where, const std::string& source) {
  if (!sel.box) {
    auto it = mesh.node_sets.find(sel.name);
    if (it == mesh.node_sets.end()) {
      std::string known;
      for (const auto& [name, nodes] : mesh.node_sets) known += (known.empty() ? "" : ", ") + name;
      throw SceneError(source + ": " + where + ".selection: no selection named \"" + sel.name +
                       "\" (the mesh has: " + known + ")");
    }
    return it->second;
  }
  // Inclusive box with a tolerance, so faces lying exactly on the box boundary are caught
  // despite round-off in generated or transformed coordinates.
  const auto& b = *sel.box;
  const double tol = 1e-9 * length_scale;
  std::vector<std::int32_t> nodes;
  for (int n = 0; n < mesh.num_local_nodes(); ++n) {
    const Vec3& X = mesh.coordinates[n];
    bool inside = true;
    for (int c = 0; c < 3; ++c) inside = inside && X[c] >= b[c] - tol && X[c] <= b[3 + c] + tol;
    if (inside) nodes.push_back(n);
  }
  return nodes;
}

}  // namespace

PrescribedMotion prescribed_motion(const Motion& m) {
  PrescribedMotion motion;
  switch (m.kind) {
    case Motion::Kind::Fixed: motion.kind = PrescribedMotion::Kind::Fixed; break;
    case Motion::Kind::Velocity: motion.kind = PrescribedMotion::Kind::Velocity; break;
    case Motion::Kind::Rotation: motion.kind = PrescribedMotion::Kind::Rotation; break;
    case Motion::Kind::Path: motion.kind = PrescribedMotion::Kind::Path; break;
  }
  motion.velocity = m.velocity;
  const double norm = std::sqrt(m.axis[0] * m.axis[0] + m.axis[1] * m.axis[1] + m.axis[2] * m.axis[2]);
  for (int c = 0; c < 3; ++c) motion.axis[c] = m.axis[c] / norm;
  motion.center = m.center;
  motion.angular_velocity = m.angular_velocity;
  motion.path = m.path;
  return motion;
}

ProblemSetup build_problem(const Scene& scene, const DistributedMesh& mesh, double length_scale) {
  ProblemSetup p;
  for (const Body& body : scene.bodies) {
    const Material& m = scene.materials[body.material];
    // Lamé parameters from (E, ν), as in docs/design.md §1.2.
    BodyMaterial bm;
    bm.lambda = m.E * m.nu / ((1 + m.nu) * (1 - 2 * m.nu));
    bm.mu = m.E / (2 * (1 + m.nu));
    bm.rho = m.rho;
    bm.volumetric = m.mean_dilatation ? VolumetricTerm::mean_dilatation : VolumetricTerm::gauss_points;
    bm.model = m.model == Material::Model::stable_neo_hookean ? MaterialModel::stable_neo_hookean
                                                              : MaterialModel::neo_hookean;
    p.body_materials.push_back(bm);
    p.body_velocity.push_back(body.initial_velocity);
    p.body_angular_velocity.push_back(body.initial_angular_velocity);
    p.body_spin_center.push_back(body.spin_center);
    p.body_kinematic.push_back(body.kinematic ? 1 : 0);
  }
  p.gravity = scene.gravity;
  p.is_static = scene.is_static;
  p.dt = scene.dt;
  p.steps = scene.steps;
  p.lumped_mass = scene.lumped_mass;
  p.length_scale = length_scale;

  if (scene.contact.enabled) {
    p.contact = true;
    ContactParameters& c = p.contact_parameters;
    c.dhat = scene.contact.dhat_relative ? scene.contact.dhat * length_scale : scene.contact.dhat;
    c.kappa_adaptive = scene.contact.kappa_adaptive;
    c.kappa = scene.contact.kappa;
    for (const Body& body : scene.bodies) {
      c.self_contact.push_back(body.self_contact ? 1 : 0);
      c.body_names.push_back(body.name);
    }
    for (const Plane& plane : scene.contact.planes) c.planes.push_back({plane.point, plane.normal});
    if (!scene.contact.obstacles.empty()) c.obstacles = load_scene_obstacles(scene, mesh.comm);
    p.friction = scene.contact.friction;
    p.friction_epsv = scene.contact.epsv;
    p.friction_iterations = scene.contact.friction_iterations;
  }

  for (const DirichletCondition& bc : scene.dirichlet) {
    DirichletSet set;
    set.local_nodes = select_nodes(bc.selection, mesh, length_scale, bc.key_path, scene.source);
    long long count = static_cast<long long>(set.local_nodes.size()), total = 0;
    MPI_Allreduce(&count, &total, 1, MPI_LONG_LONG, MPI_SUM, mesh.comm);
    if (total == 0)
      throw SceneError(scene.source + ": " + bc.key_path + ".selection: " + bc.selection.describe() +
                       " selects no node");
    set.motion = prescribed_motion(bc);
    p.dirichlet.push_back(std::move(set));
  }
  return p;
}

}  // namespace dipc
