// Scene file parser: reads the JSON format documented below into a Scene and validates every
// value, so that the solver never starts on a scene with a typo or an impossible parameter.
//
// A scene in PolyFEM's own format is recognised by is_polyfem_scene() and translated by
// polyfem_scene.cpp instead.
// Format (in the spirit of PolyFEM's JSON scenes; tests/io/data/ holds complete examples):
//   materials            [ {name, E, nu, rho, model: neo_hookean|stable_neo_hookean,
//                           volumetric: gauss_points|mean_dilatation} ]  required, >= 1
//                        (mean_dilatation with the neo_hookean model only)
//   geometry             [ {name, box: {size, resolution, origin} | mesh,
//                           translation, scale (mesh only), material, initial_velocity,
//                           initial_spin: {angular_velocity: [wx,wy,wz], center: [x,y,z]},
//                           self_contact, kinematic: {MOTION}} ]      required, >= 1
//   boundary_conditions  {gravity: [gx,gy,gz], dirichlet: [ {selection, MOTION} ]}
//   time                 {integrator: implicit_euler, dt, steps | t_end} or
//                        {integrator: static, dt, steps} (load steps; default 1, 1) required
//   solver               {mass: lumped|consistent}
//   output               {directory, name, every}
//   contact              {enabled, dhat, dhat_relative, barrier_stiffness: "adaptive" | κ,
//                         friction, epsv, friction_iterations,
//                         planes: [ {point: [x,y,z], normal: [nx,ny,nz]} ],
//                         obstacles: [ {name, mesh: OBJ | STL, scale, translation,
//                                       motion: {MOTION}} ]}
// where MOTION is  type: fixed | velocity (with velocity) | rotation (with axis, center,
// angular_velocity) | path (with keyframes: [ {time, translation: [dx,dy,dz]} ], the first
// {time: 0, translation: [0,0,0]}); type defaults to fixed.
// Omitted optional values take the defaults of scene.hpp. A body's name defaults to
// "body<i>"; its material may be omitted when the scene has exactly one. A selection is a
// node set name ("beam.xmin") or {"box": [[xmin,ymin,zmin],[xmax,ymax,zmax]]}.
// A kinematic body is prescribed entirely: its motion becomes a DirichletCondition on the node
// set <name> (all its nodes), appended after those of boundary_conditions.dirichlet with key
// path "geometry[i].kinematic"; initial_velocity and named selections of its nodes in
// boundary_conditions are rejected because they would contradict that motion.
// contact.dhat is an activation DISTANCE (length, not squared); with dhat_relative (default)
// it is a fraction of the bounding-box diagonal of the bodies, so it must be < 1. A plane is a
// half-space obstacle whose solid lies behind its normal (normalised here).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "io/json_document.hpp"
#include "io/polyfem_scene.hpp"
#include "io/scene.hpp"
#include "io/scene_json_node.hpp"
#include "math/number_text.hpp"
#include "math/vector3.hpp"
#include "mesh/mesh_checks.hpp"

namespace dipc {
namespace {

double positive(const SceneJsonNode& node) {
  const double v = node.number();
  if (!(v > 0)) node.fail_value("must be > 0");
  return v;
}

// The smallest time step that double precision can take. Newton ends a step when the largest
// position increment per unit time, |p|_inf / dt, is below the velocity tolerance, by default
// 1e-5 scene diagonals per second (-dipc_velocity_tol_rel). Positions carry rounding errors of
// eps·|x|, at least eps/2 of the diagonal (the largest |x| is at least half the diagonal), so
// below dt = (eps/2) / 1e-5 ≈ 1.1e-11 s rounding alone exceeds the tolerance and the test decides
// nothing: steps end on an exactly zero gradient with the motion lost (dt²·|g| and dt·|v| vanish
// against the positions), or never converge. A factor of 10 above that leaves the test a margin.
constexpr double kSmallestTimeStep = 1e-10;

double time_step(const SceneJsonNode& node) {
  const double dt = positive(node);
  if (dt < kSmallestTimeStep)
    node.fail_value("below " + format_number(kSmallestTimeStep) +
                    " s, where rounding of the positions exceeds Newton's velocity tolerance");
  return dt;
}

std::vector<Material> parse_materials(const SceneJsonNode& node) {
  const std::vector<SceneJsonNode> items = node.elements();
  if (items.empty()) node.fail("must list at least one material");
  std::vector<Material> materials;
  std::map<std::string, std::string> first_path_of_name;
  for (const SceneJsonNode& item : items) {
    item.expect_object({"name", "E", "nu", "rho", "model", "volumetric"});
    Material m;
    if (auto name = item.find("name")) {
      m.name = name->string();
      if (m.name.empty()) name->fail("must not be empty");
      const auto [it, inserted] = first_path_of_name.emplace(m.name, name->path());
      if (!inserted) name->fail_value("duplicate material name (also " + it->second + ")");
    }
    if (auto E = item.find("E")) m.E = positive(*E);
    if (auto nu = item.find("nu")) {
      m.nu = nu->number();
      // Strict bounds: nu = 0.5 makes lambda = E nu / ((1 + nu)(1 - 2 nu)) infinite and
      // nu = -1 makes mu = E / (2 (1 + nu)) infinite.
      if (!(m.nu > -1.0 && m.nu < 0.5)) nu->fail_value("must be in (-1, 0.5)");
    }
    if (auto rho = item.find("rho")) m.rho = positive(*rho);
    if (auto volumetric = item.find("volumetric")) {
      const std::string v = volumetric->string();
      if (v != "gauss_points" && v != "mean_dilatation")
        volumetric->fail_value("must be \"gauss_points\" or \"mean_dilatation\"");
      m.mean_dilatation = v == "mean_dilatation";
    }
    if (auto model = item.find("model")) {
      const std::string v = model->string();
      if (v != "neo_hookean" && v != "stable_neo_hookean")
        model->fail_value("must be \"neo_hookean\" or \"stable_neo_hookean\"");
      m.model = v == "stable_neo_hookean" ? Material::Model::stable_neo_hookean : Material::Model::neo_hookean;
      if (m.model != Material::Model::neo_hookean && m.mean_dilatation)
        model->fail_value("has no mean-dilatation element (volumetric \"mean_dilatation\" is neo_hookean only; "
                          "use volumetric \"gauss_points\")");
    }
    materials.push_back(m);
  }
  return materials;
}

std::size_t material_reference(const std::optional<SceneJsonNode>& node, const SceneJsonNode& body,
                               const std::vector<Material>& materials) {
  if (!node) {
    if (materials.size() == 1) return 0;
    body.fail("\"material\" is required when the scene has " + std::to_string(materials.size()) + " materials");
  }
  if (node->json().is_string()) {
    const std::string name = node->string();
    std::string known;
    for (std::size_t i = 0; i < materials.size(); ++i) {
      if (materials[i].name == name) return i;
      if (!materials[i].name.empty()) known += (known.empty() ? "" : ", ") + materials[i].name;
    }
    node->fail_value("unknown material (known: " + (known.empty() ? "none named" : known) + ")");
  }
  if (!node->json().is_number_integer()) node->fail("expected a material name or index");
  const int index = node->integer();
  if (index < 0 || static_cast<std::size_t>(index) >= materials.size()) {
    node->fail_value("material index must be in [0, " + std::to_string(materials.size()) + ")");
  }
  return static_cast<std::size_t>(index);
}

// A box's elements are rectangular, with det J = hx·hy·hz / 8 everywhere (edges h = size /
// resolution, the reference element [-1, 1]^3). Elements that check_mesh would call degenerate
// (det J at most kDegenerateJacobianRatio times the longest edge cubed) are refused here, naming
// box.size: a file mesh gets that message, and a box so flat would otherwise end in a contact or
// solver failure far from its cause. -dipc_refine scales every edge alike, so the ratio stays.
void check_box_elements(const BoxGenerator& box, const SceneJsonNode& size) {
  double h[3];
  for (int c = 0; c < 3; ++c) h[c] = box.size[c] / box.resolution[c];
  const double longest = std::max({h[0], h[1], h[2]});
  if (h[0] * h[1] * h[2] / 8 > kDegenerateJacobianRatio * longest * longest * longest) return;
  size.fail_value("its elements, " + format_number(h[0]) + " x " + format_number(h[1]) + " x " + format_number(h[2]) +
                  ", are degenerate (det J at most " + format_number(kDegenerateJacobianRatio) +
                  " times the longest edge cubed)");
}

BoxGenerator parse_box(const SceneJsonNode& node) {
  node.expect_object({"size", "resolution", "origin"});
  BoxGenerator box;
  if (auto size = node.find("size")) {
    box.size = size->vec3();
    for (const SceneJsonNode& s : size->elements()) positive(s);
  }
  if (auto resolution = node.find("resolution")) {
    const std::vector<SceneJsonNode> items = resolution->elements();
    if (items.size() != 3) resolution->fail("expected an array of 3 integers, got " + std::to_string(items.size()));
    for (int d = 0; d < 3; ++d) {
      box.resolution[d] = items[d].integer();
      if (box.resolution[d] < 1) items[d].fail_value("must be >= 1");
    }
  }
  if (auto origin = node.find("origin")) box.origin = origin->vec3();
  if (auto size = node.find("size")) check_box_elements(box, *size);
  return box;
}

// A path's keyframes: [{time, translation}], at least two, the first (0, [0, 0, 0]) so that the
// motion starts at the rest placement, times strictly increasing.
std::vector<std::array<double, 4>> parse_path(const SceneJsonNode& node) {
  const std::vector<SceneJsonNode> items = node.elements();
  if (items.size() < 2) node.fail("a path needs at least two keyframes, got " + std::to_string(items.size()));
  std::vector<std::array<double, 4>> path;
  for (std::size_t k = 0; k < items.size(); ++k) {
    const SceneJsonNode& item = items[k];
    item.expect_object({"time", "translation"});
    const SceneJsonNode time = item.required("time");
    const double t = time.number();
    const std::array<double, 3> d = item.required("translation").vec3();
    if (k == 0 && t != 0) time.fail_value("the first keyframe must be at time 0");
    if (k == 0 && (d[0] != 0 || d[1] != 0 || d[2] != 0))
      item.required("translation")
          .fail_value("the first keyframe's translation must be [0, 0, 0] (the rest placement)");
    if (k > 0 && !(t > path.back()[0]))
      time.fail_value("keyframe times must strictly increase (previous " + format_number(path.back()[0]) + ")");
    path.push_back({t, d[0], d[1], d[2]});
  }
  return path;
}

// Reads a prescribed motion (of a Dirichlet condition, kinematic body or obstacle): "type" and
// the keys that type takes. `other_keys` are the keys the enclosing object may hold besides these.
void parse_motion(const SceneJsonNode& node, const std::vector<std::string>& other_keys, Motion& motion) {
  std::string type = "fixed";
  if (auto t = node.find("type")) {
    type = t->string();
    if (type == "fixed") {
      motion.kind = Motion::Kind::Fixed;
    } else if (type == "velocity") {
      motion.kind = Motion::Kind::Velocity;
    } else if (type == "rotation") {
      motion.kind = Motion::Kind::Rotation;
    } else if (type == "path") {
      motion.kind = Motion::Kind::Path;
    } else {
      t->fail_value("unknown type (allowed: fixed, velocity, rotation, path)");
    }
  }
  std::vector<std::string> allowed = other_keys;
  allowed.push_back("type");
  const std::string context = "for type \"" + type + "\"";
  switch (motion.kind) {
    case Motion::Kind::Fixed: node.expect_object(allowed, context); break;
    case Motion::Kind::Velocity:
      allowed.push_back("velocity");
      node.expect_object(allowed, context);
      motion.velocity = node.required("velocity").vec3();
      break;
    case Motion::Kind::Rotation: {
      for (const char* key : {"axis", "center", "angular_velocity"}) allowed.push_back(key);
      node.expect_object(allowed, context);
      if (auto axis = node.find("axis")) {
        const std::array<double, 3> a = axis->vec3();
        const double length = std::sqrt(squared_norm3(a.data()));
        if (!(length > 0)) axis->fail_value("rotation axis must be non-zero");
        motion.axis = {a[0] / length, a[1] / length, a[2] / length};
      }
      if (auto center = node.find("center")) motion.center = center->vec3();
      motion.angular_velocity = node.required("angular_velocity").number();
      break;
    }
    case Motion::Kind::Path:
      allowed.push_back("keyframes");
      node.expect_object(allowed, context);
      motion.path = parse_path(node.required("keyframes"));
      break;
  }
}

// Bodies, plus the Dirichlet conditions that their "kinematic" motions stand for.
struct Geometry {
  std::vector<Body> bodies;
  std::vector<DirichletCondition> kinematic_motions;
};

Geometry parse_geometry(const SceneJsonNode& node, const std::vector<Material>& materials,
                        const std::string& base_directory) {
  const std::vector<SceneJsonNode> items = node.elements();
  if (items.empty()) node.fail("must list at least one body");
  Geometry geometry;
  std::vector<Body>& bodies = geometry.bodies;
  std::map<std::string, std::string> first_path_of_name;
  for (std::size_t i = 0; i < items.size(); ++i) {
    const SceneJsonNode& item = items[i];
    item.expect_object({"name", "box", "mesh", "translation", "scale", "material", "initial_velocity", "initial_spin",
                        "self_contact", "kinematic"});
    Body b;
    b.name = "body" + std::to_string(i);
    if (auto name = item.find("name")) {
      b.name = name->string();
      if (b.name.empty()) name->fail("must not be empty");
      // Selections are "<body>.<set>": a dot inside a body name would make them ambiguous.
      if (b.name.find('.') != std::string::npos) name->fail_value("must not contain '.'");
    }
    const auto [it, inserted] = first_path_of_name.emplace(b.name, item.path());
    if (!inserted) item.fail("duplicate body name \"" + b.name + "\" (also " + it->second + ")");

    const auto box = item.find("box");
    const auto mesh = item.find("mesh");
    if (box && mesh) item.fail("give either \"box\" or \"mesh\", not both");
    if (!box && !mesh) item.fail("needs a \"box\" or a \"mesh\"");
    if (box) {
      b.box = parse_box(*box);
      for (const char* key : {"translation", "scale"}) {
        if (auto placed = item.find(key)) {
          placed->fail("applies to a \"mesh\" body only (a box is placed by box.origin and box.size)");
        }
      }
    } else {
      b.mesh_file = resolve_mesh_path(*mesh, base_directory);
      if (auto translation = item.find("translation")) b.translation = translation->vec3();
      if (auto scale = item.find("scale")) b.scale = positive(*scale);
    }
    b.material = material_reference(item.find("material"), item, materials);
    if (auto v = item.find("initial_velocity")) b.initial_velocity = v->vec3();
    if (auto spin = item.find("initial_spin")) {
      spin->expect_object({"angular_velocity", "center"});
      b.initial_angular_velocity = spin->required("angular_velocity").vec3();
      b.spin_center = spin->required("center").vec3();
    }
    if (auto self_contact = item.find("self_contact")) b.self_contact = self_contact->boolean();
    if (auto kinematic = item.find("kinematic")) {
      b.kinematic = true;
      for (const char* key : {"initial_velocity", "initial_spin"})
        if (auto v = item.find(key))
          v->fail("a kinematic body's motion is prescribed by \"kinematic\", not by an initial velocity");
      DirichletCondition motion;
      motion.key_path = kinematic->path();
      parse_motion(*kinematic, {}, motion);
      motion.selection.name = b.name;  // the node set of all the body's nodes
      geometry.kinematic_motions.push_back(motion);
    }
    bodies.push_back(b);
  }
  return geometry;
}

Selection parse_selection(const SceneJsonNode& node) {
  Selection s;
  if (node.json().is_string()) {
    s.name = node.string();
    if (s.name.empty()) node.fail("must not be empty");
    return s;
  }
  if (!node.json().is_object()) node.fail("expected a node set name or {\"box\": [[min], [max]]}");
  node.expect_object({"box"});
  const SceneJsonNode box = node.required("box");
  const std::vector<SceneJsonNode> corners = box.elements();
  if (corners.size() != 2) box.fail("expected [[xmin, ymin, zmin], [xmax, ymax, zmax]]");
  const std::array<double, 3> lo = corners[0].vec3();
  const std::array<double, 3> hi = corners[1].vec3();
  for (int d = 0; d < 3; ++d) {
    if (lo[d] > hi[d]) {
      box.fail("min corner exceeds max corner in coordinate " + std::to_string(d) + " (" + format_number(lo[d]) +
               " > " + format_number(hi[d]) + ")");
    }
  }
  s.box = std::array<double, 6>{lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]};
  return s;
}

DirichletCondition parse_dirichlet(const SceneJsonNode& node, const std::vector<Body>& bodies) {
  DirichletCondition bc;
  bc.key_path = node.path();
  parse_motion(node, {"selection"}, bc);
  const SceneJsonNode selection = node.required("selection");
  bc.selection = parse_selection(selection);
  // A named set of a kinematic body ("<body>" or "<body>.<set>") would prescribe its nodes
  // twice. Box selections depend on the mesh and are not checked here.
  if (!bc.selection.box) {
    const std::string body_name = bc.selection.name.substr(0, bc.selection.name.find('.'));
    for (std::size_t i = 0; i < bodies.size(); ++i) {
      if (bodies[i].kinematic && bodies[i].name == body_name) {
        selection.fail_value("body \"" + body_name + "\" is kinematic (geometry[" + std::to_string(i) +
                             "].kinematic prescribes all its nodes)");
      }
    }
  }
  return bc;
}

void parse_boundary_conditions(const SceneJsonNode& node, Scene& scene) {
  node.expect_object({"gravity", "dirichlet"});
  if (auto g = node.find("gravity")) scene.gravity = g->vec3();
  if (auto dirichlet = node.find("dirichlet")) {
    for (const SceneJsonNode& item : dirichlet->elements()) {
      scene.dirichlet.push_back(parse_dirichlet(item, scene.bodies));
    }
  }
}

void parse_time(const SceneJsonNode& node, Scene& scene) {
  if (auto integrator = node.find("integrator")) {
    const std::string name = integrator->string();
    if (name == "static") {
      scene.is_static = true;
    } else if (name != "implicit_euler") {
      integrator->fail_value("unknown integrator (allowed: implicit_euler, static)");
    }
  }
  if (scene.is_static) {
    // A static run is a sequence of load steps: step k minimises the elastic and body energy
    // with the prescribed motions evaluated at the pseudo-time k·dt (default: one step, dt 1).
    node.expect_object({"integrator", "dt", "steps"}, "for integrator \"static\"");
    scene.dt = 1.0;
    scene.steps = 1;
    if (auto dt = node.find("dt")) scene.dt = time_step(*dt);
    if (auto steps = node.find("steps")) {
      scene.steps = steps->integer();
      if (scene.steps < 1) steps->fail_value("must be >= 1");
    }
    return;
  }
  node.expect_object({"integrator", "dt", "steps", "t_end"});
  scene.dt = time_step(node.required("dt"));
  const auto steps = node.find("steps");
  const auto t_end = node.find("t_end");
  if (steps && t_end) node.fail("give either \"steps\" or \"t_end\", not both");
  if (!steps && !t_end) node.fail("needs \"steps\" or \"t_end\"");
  if (steps) {
    scene.steps = steps->integer();
    if (scene.steps < 1) steps->fail_value("must be >= 1");
    return;
  }
  const double end = positive(*t_end);
  const double ratio = end / scene.dt;
  if (!(ratio < 2147483647.0)) {
    t_end->fail_value("needs more than 2147483647 steps of dt = " + format_number(scene.dt));
  }
  const long long n = std::llround(ratio);
  if (n < 1) t_end->fail_value("shorter than one step of dt = " + format_number(scene.dt));
  if (std::abs(static_cast<double>(n) * scene.dt - end) > 1e-9 * end) {
    t_end->fail_value("not a whole number of steps of dt = " + format_number(scene.dt) + " (" + format_number(ratio) +
                      " steps)");
  }
  scene.steps = static_cast<int>(n);
}

void parse_solver(const SceneJsonNode& node, Scene& scene) {
  node.expect_object({"mass"});
  if (auto mass = node.find("mass")) {
    const std::string kind = mass->string();
    if (kind == "lumped") {
      scene.lumped_mass = true;
    } else if (kind == "consistent") {
      scene.lumped_mass = false;
    } else {
      mass->fail_value("unknown mass matrix (allowed: lumped, consistent)");
    }
  }
}

void parse_output(const SceneJsonNode& node, Scene& scene) {
  node.expect_object({"directory", "name", "every"});
  if (auto directory = node.find("directory")) {
    scene.output_directory = directory->string();
    if (scene.output_directory.empty()) directory->fail("must not be empty");
  }
  if (auto name = node.find("name")) {
    scene.output_name = name->string();
    // The name becomes <name>.h5 and <name>.xmf inside the output directory.
    if (scene.output_name.empty() || scene.output_name.find('/') != std::string::npos) {
      name->fail_value("must be a non-empty file name without '/'");
    }
  }
  if (auto every = node.find("every")) {
    scene.output_every = every->integer();
    if (scene.output_every < 1) every->fail_value("must be >= 1");
  }
}

void parse_barrier_stiffness(const SceneJsonNode& node, ContactSettings& contact) {
  if (node.json().is_string()) {
    if (node.string() != "adaptive")
      node.fail_value("unknown barrier stiffness (allowed: \"adaptive\" or a number > 0)");
    contact.kappa_adaptive = true;
    contact.kappa = 0;
    return;
  }
  if (!node.json().is_number()) node.fail("expected \"adaptive\" or a number > 0");
  contact.kappa_adaptive = false;
  contact.kappa = positive(node);
}

// Triangle-mesh obstacles: [{name, mesh, scale, translation, motion}]; the file is read later
// (app/scene_obstacles.cpp), where its faces are checked.
std::vector<Obstacle> parse_obstacles(const SceneJsonNode& node, const std::string& base_directory) {
  std::vector<Obstacle> obstacles;
  std::map<std::string, std::string> first_path_of_name;
  const std::vector<SceneJsonNode> items = node.elements();
  for (std::size_t i = 0; i < items.size(); ++i) {
    const SceneJsonNode& item = items[i];
    item.expect_object({"name", "mesh", "scale", "translation", "motion"});
    Obstacle o;
    o.key_path = item.path();
    o.name = "obstacle" + std::to_string(i);
    if (auto name = item.find("name")) {
      o.name = name->string();
      if (o.name.empty()) name->fail("must not be empty");
    }
    const auto [it, inserted] = first_path_of_name.emplace(o.name, item.path());
    if (!inserted) item.fail("duplicate obstacle name \"" + o.name + "\" (also " + it->second + ")");
    o.mesh_file = resolve_mesh_path(item.required("mesh"), base_directory);
    if (auto scale = item.find("scale")) o.scale = positive(*scale);
    if (auto translation = item.find("translation")) o.translation = translation->vec3();
    if (auto motion = item.find("motion")) parse_motion(*motion, {}, o.motion);
    obstacles.push_back(o);
  }
  return obstacles;
}

std::vector<Plane> parse_planes(const SceneJsonNode& node) {
  std::vector<Plane> planes;
  for (const SceneJsonNode& item : node.elements()) {
    item.expect_object({"point", "normal"});
    Plane plane;
    plane.point = item.required("point").vec3();
    const SceneJsonNode normal = item.required("normal");
    const std::array<double, 3> n = normal.vec3();
    const double length = std::sqrt(squared_norm3(n.data()));
    if (!(length > 0)) normal.fail_value("plane normal must be non-zero");
    plane.normal = {n[0] / length, n[1] / length, n[2] / length};
    planes.push_back(plane);
  }
  return planes;
}

void parse_contact(const SceneJsonNode& node, ContactSettings& contact, const std::string& base_directory) {
  node.expect_object({"enabled", "dhat", "dhat_relative", "barrier_stiffness", "friction", "epsv",
                      "friction_iterations", "planes", "obstacles"});
  if (auto enabled = node.find("enabled")) contact.enabled = enabled->boolean();
  if (auto relative = node.find("dhat_relative")) contact.dhat_relative = relative->boolean();
  if (auto dhat = node.find("dhat")) {
    contact.dhat = positive(*dhat);
    // d̂ at or beyond the whole scene's diagonal would make every primitive pair active.
    if (contact.dhat_relative && !(contact.dhat < 1)) {
      dhat->fail_value("a relative dhat is a fraction of the bounding-box diagonal, must be < 1");
    }
  }
  if (auto kappa = node.find("barrier_stiffness")) parse_barrier_stiffness(*kappa, contact);
  if (auto friction = node.find("friction")) {
    contact.friction = friction->number();
    if (contact.friction < 0) friction->fail_value("must be >= 0");
  }
  if (auto epsv = node.find("epsv")) contact.epsv = positive(*epsv);
  if (auto iterations = node.find("friction_iterations")) {
    contact.friction_iterations = iterations->integer();
    if (contact.friction_iterations < 1) iterations->fail_value("must be >= 1");
  }
  if (auto planes = node.find("planes")) contact.planes = parse_planes(*planes);
  if (auto obstacles = node.find("obstacles")) {
    contact.obstacles = parse_obstacles(*obstacles, base_directory);
    // Without contact nothing would see them: say so rather than run through them.
    if (!contact.enabled && !contact.obstacles.empty())
      obstacles->fail("triangle-mesh obstacles need contact (\"enabled\": true)");
  }
}

}  // namespace

std::string Selection::describe() const {
  if (box) {
    const std::array<double, 6>& b = *box;
    return "box [" + format_number(b[0]) + ", " + format_number(b[1]) + ", " + format_number(b[2]) + "] - [" +
           format_number(b[3]) + ", " + format_number(b[4]) + ", " + format_number(b[5]) + "]";
  }
  return "node set \"" + name + "\"";
}

Motion parse_motion_text(const std::string& json_text, const std::string& source_name) {
  const nlohmann::json document = parse_json_document(json_text, source_name);
  const SceneJsonNode root(document, "", source_name);
  Motion motion;
  parse_motion(root, {}, motion);
  return motion;
}

Scene parse_scene_text(const std::string& json_text, const std::string& source_name,
                       const std::string& base_directory) {
  const nlohmann::json document = parse_json_document(json_text, source_name);
  // A PolyFEM file's errors say why it was read as one: a typo in a dipc scene can be a
  // PolyFEM key ("tend" for "t_end").
  if (const std::string marker = polyfem_marker(document); !marker.empty()) {
    try {
      return translate_polyfem_scene(document, source_name, base_directory);
    } catch (const SceneError& e) {
      throw SceneError(std::string(e.what()) + " [read in PolyFEM's format: it has " + marker + "]");
    }
  }
  const SceneJsonNode root(document, "", source_name);
  root.expect_object({"materials", "geometry", "boundary_conditions", "time", "solver", "output", "contact"});

  Scene scene;
  scene.source = source_name;
  scene.materials = parse_materials(root.required("materials"));
  Geometry geometry = parse_geometry(root.required("geometry"), scene.materials, base_directory);
  scene.bodies = std::move(geometry.bodies);
  if (auto bc = root.find("boundary_conditions")) parse_boundary_conditions(*bc, scene);
  for (DirichletCondition& motion : geometry.kinematic_motions) scene.dirichlet.push_back(std::move(motion));
  parse_time(root.required("time"), scene);
  if (auto solver = root.find("solver")) parse_solver(*solver, scene);
  if (auto output = root.find("output")) parse_output(*output, scene);
  if (auto contact = root.find("contact")) parse_contact(*contact, scene.contact, base_directory);
  return scene;
}

Scene parse_scene_file(const std::string& path) {
  // An ifstream opens a directory and then reads nothing, which would read as invalid JSON.
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw SceneError(path + ": is a directory, not a scene file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw SceneError(path + ": cannot open scene file");
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw SceneError(path + ": cannot read scene file");
  const std::filesystem::path base = std::filesystem::absolute(path).parent_path();
  return parse_scene_text(text.str(), path, base.string());
}

}  // namespace dipc
