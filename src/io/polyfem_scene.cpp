// PolyFEM scene → dipc Scene. Meanings and defaults follow PolyFEM's specification
// (json-specs/input-spec.json, material-parameters.json, selection.json) and its readers:
//  - transformation: x = R·diag(scale)·X + translation (mesh/GeometryReader.cpp: scale first,
//    then rotate about the origin, then translate); a list `dimensions` replaces `scale` by the
//    factors that give the mesh's bounding box those sizes (io/bounding_box_scale.hpp), a
//    number there is ignored as PolyFEM ignores it; rotation in degrees, rotation_mode "xyz"
//    (default; any sequence of x, y, z applied left to right, each angle read from the entry of
//    its axis), "axis_angle" [deg, ax, ay, az], "quaternion" [x, y, z, w] or
//    "rotation_vector" (degrees) (utils/JSONUtils.cpp, to_rotation_matrix).
//  - materials: NeoHookean with E, nu (or lambda, mu), rho (default 1), chosen by volume id
//    (id default 0); a body's volume id is geometry[i].volume_selection (default 0).
//  - rhs: the body force as PolyFEM's energy takes it, +∫ ρ rhs·u (assembler/RhsAssembler.cpp,
//    compute_energy), so the acceleration of gravity is −rhs: "rhs": [0, 9.81, 0] is gravity
//    along −y.
//  - dirichlet_boundary / obstacle_displacements: prescribed displacements u(t) on surface
//    selection ids; PolyFEM evaluates them at the step times t = k·dt. dipc takes a uniform
//    (position-independent) one as `fixed`, `velocity` (u = v t) or, otherwise, a piecewise
//    linear `path` through its values at every step time, which gives the same values where
//    PolyFEM samples it.
//  - time: two of dt, time_steps, tend (tend with dt: ceil(tend/dt) steps, State.cpp);
//    ImplicitEuler (= BDF of order 1); quasistatic → dipc's static load steps.
//  - contact.dhat is absolute (default 1e-3); PolyFEM lowers a dhat it was not given to
//    dhat_percentage × the shortest boundary edge when that edge is shorter than 1e-3, which
//    dipc does not (the note says so).
//  - mass: consistent unless solver.advanced.lump_mass_matrix.
#include "io/polyfem_scene.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <set>

#include "io/polyfem_common.hpp"
#include "io/polyfem_expression.hpp"
#include "io/scene_json_node.hpp"
#include "math/number_text.hpp"
#include "math/vector3.hpp"

namespace dipc {
namespace {

constexpr const char* kNotModelled = "dipc cannot model this: ";

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

// Elements of an array, or the value itself where PolyFEM takes either (geometry, materials,
// selections).
std::vector<SceneJsonNode> one_or_many(const SceneJsonNode& node) {
  if (node.json().is_array()) return node.elements();
  return {node};
}

bool has_any(const nlohmann::json& object, std::initializer_list<const char*> keys) {
  if (!object.is_object()) return false;
  for (const char* key : keys)
    if (object.contains(key)) return true;
  return false;
}

// A PolyFEM value: a number or an expression of x, y, z, t.
PolyfemExpression expression(const SceneJsonNode& node) {
  if (node.json().is_number()) {
    node.number();  // rejects non-finite numbers
    return PolyfemExpression(node.json().dump());
  }
  if (!node.json().is_string())
    node.fail(std::string(kNotModelled) + "expected a number or an expression of x, y, z, t (PolyFEM's values "
                                          "with units, from files or from Python functions are not read)");
  try {
    return PolyfemExpression(node.string());
  } catch (const std::invalid_argument& e) {
    node.fail_value(std::string("not an expression dipc reads: ") + e.what());
  }
}

std::vector<PolyfemExpression> expression3(const SceneJsonNode& node) {
  const std::vector<SceneJsonNode> items = node.elements();
  if (items.size() != 3) node.fail("expected 3 values (x, y, z), got " + std::to_string(items.size()));
  std::vector<PolyfemExpression> e;
  for (const SceneJsonNode& item : items) e.push_back(expression(item));
  return e;
}

// A vector that must be the same everywhere and at every time (body force, initial velocity).
std::array<double, 3> constant3(const SceneJsonNode& node, const std::string& why) {
  const std::vector<PolyfemExpression> e = expression3(node);
  for (int c = 0; c < 3; ++c)
    if (e[c].uses_position() || e[c].uses_time())
      node.elements()[c].fail_value(std::string(kNotModelled) + "it varies in space or time; " + why);
  return {e[0].evaluate(0, 0, 0, 0), e[1].evaluate(0, 0, 0, 0), e[2].evaluate(0, 0, 0, 0)};
}

double constant_number(const SceneJsonNode& node, const std::string& why) {
  if (!node.json().is_number()) node.fail(std::string(kNotModelled) + "expected a number; " + why);
  return node.number();
}

std::vector<int> ids_of(const SceneJsonNode& node) {
  std::vector<int> ids;
  if (node.json().is_array()) {
    for (const SceneJsonNode& item : node.elements()) ids.push_back(item.integer());
  } else if (node.json().is_string()) {
    node.fail_value(std::string(kNotModelled) + "give the ids as integers (\"all\" is not read)");
  } else {
    ids.push_back(node.integer());
  }
  return ids;
}

struct Translator {
  std::string source;
  std::string base_directory;
  Scene scene;
  // Per dipc body: its PolyFEM volume id. Per obstacle: its surface id (or none).
  std::vector<int> volume_id;
  std::vector<std::optional<int>> obstacle_id;
  std::vector<std::string> obstacle_key;  // "geometry[i]" of each obstacle

  void note(const SceneJsonNode& node, const std::string& what) {
    scene.notes.push_back(source + ": " + node.path() + ": " + what);
  }

  // ---- materials ----------------------------------------------------------------------------
  struct MaterialIds {
    std::vector<int> ids;  // empty: every volume id (a single material object)
  };
  std::vector<MaterialIds> material_ids;

  void materials(const SceneJsonNode& node) {
    const bool single = node.json().is_object();
    const std::vector<SceneJsonNode> items = one_or_many(node);
    if (items.empty()) node.fail("must list at least one material");
    for (const SceneJsonNode& item : items) {
      item.expect_object({"type", "id", "E", "nu", "lambda", "mu", "rho", "phi", "psi"});
      const SceneJsonNode type = item.required("type");
      if (type.string() != "NeoHookean")
        type.fail_value(std::string(kNotModelled) + "dipc's material is NeoHookean (compressible neo-Hookean)");
      const std::string why = "dipc takes constant material parameters";
      Material m;
      m.name = item.path();
      const auto E = item.find("E"), nu = item.find("nu"), lambda = item.find("lambda"), mu = item.find("mu");
      if ((E || nu) && (lambda || mu)) item.fail("give E and nu, or lambda and mu, not both");
      if (E || nu) {
        if (!E) item.required("E");
        if (!nu) item.required("nu");
        m.E = constant_number(*E, why);
        m.nu = constant_number(*nu, why);
      } else {
        const double l = constant_number(item.required("lambda"), why), u = constant_number(item.required("mu"), why);
        if (!(u > 0) || !(l + u > 0))
          item.fail("lambda = " + format_number(l) + ", mu = " + format_number(u) +
                    ": must have mu > 0 and lambda + mu > 0");
        // Young's modulus and Poisson's ratio from the Lamé parameters (any elasticity text).
        m.E = u * (3 * l + 2 * u) / (l + u);
        m.nu = l / (2 * (l + u));
      }
      if (!(m.E > 0)) (E ? *E : item).fail_value("Young's modulus must be > 0");
      if (!(m.nu > -1 && m.nu < 0.5)) (nu ? *nu : item).fail_value("Poisson's ratio must be in (-1, 0.5)");
      m.rho = 1;  // PolyFEM's default density
      if (auto rho = item.find("rho")) {
        m.rho = constant_number(*rho, why);
        if (!(m.rho > 0)) rho->fail_value("must be > 0");
      }
      for (const char* damping : {"phi", "psi"})
        if (auto d = item.find(damping))
          if (constant_number(*d, why) != 0) d->fail_value(std::string(kNotModelled) + "dipc has no viscous damping");
      MaterialIds ids;
      if (!single) ids.ids = item.find("id") ? ids_of(*item.find("id")) : std::vector<int>{0};
      scene.materials.push_back(m);
      material_ids.push_back(ids);
    }
  }

  std::size_t material_of(int volume, const SceneJsonNode& body) {
    for (std::size_t k = 0; k < material_ids.size(); ++k) {
      const std::vector<int>& ids = material_ids[k].ids;
      if (ids.empty() || std::find(ids.begin(), ids.end(), volume) != ids.end()) return k;
    }
    body.fail("no material has id " + std::to_string(volume) + " (this body's volume id)");
  }

  // ---- geometry -----------------------------------------------------------------------------
  // x = linear·diag(f)·X + translation from PolyFEM's transformation, f the factors that give
  // the mesh's bounding box the sizes `dimensions` (computed by the app, which reads the mesh).
  void transformation(const SceneJsonNode& node, bool obstacle, std::array<double, 9>& linear,
                      std::array<double, 3>& translation, std::optional<std::array<double, 3>>& dimensions) {
    node.expect_object({"translation", "rotation", "rotation_mode", "scale", "dimensions"});
    std::array<double, 3> s{1, 1, 1};
    if (auto d = node.find("dimensions")) {
      if (d->json().is_number()) {
        // The specification's default for an absent key is the number 1, so PolyFEM scales to
        // a bounding box only for a list and ignores a number.
        d->number();
        note(*d, "a number: ignored, as PolyFEM ignores it (only a list of 3 sizes scales the mesh)");
      } else {
        dimensions = bounding_box_sizes(*d, obstacle);
        if (auto scale = node.find("scale"))
          note(*scale, "ignored: dimensions is given, which replaces scale (PolyFEM's rule)");
      }
    }
    if (auto scale = node.find("scale"); scale && !dimensions) {
      if (scale->json().is_number()) {
        s = {scale->number(), scale->number(), scale->number()};
      } else if (!scale->json().empty()) {
        s = scale->vec3();
      }
      for (double f : s)
        if (!(f > 0)) scale->fail_value("scale factors must be > 0 (dipc's hexahedra must keep det J > 0)");
    }
    std::array<double, 9> R{1, 0, 0, 0, 1, 0, 0, 0, 1};
    if (auto rotation = node.find("rotation")) {
      std::string mode = "xyz";
      if (auto m = node.find("rotation_mode")) mode = lower(m->string());
      R = rotation_matrix(*rotation, mode);
    }
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) linear[3 * r + c] = R[3 * r + c] * s[c];
    if (auto t = node.find("translation")) {
      if (!t->json().empty()) translation = t->vec3();
    }
  }

  // transformation.dimensions as a list: 3 finite sizes >= 0, not all 0; > 0 for a body, whose
  // hexahedra a zero size would flatten. A 0 for an obstacle is checked against its mesh where
  // the mesh is read (allowed only along an axis where the mesh is flat, as a plane.obj is).
  std::array<double, 3> bounding_box_sizes(const SceneJsonNode& node, bool obstacle) {
    if (!node.json().is_array()) node.fail("expected a list of 3 bounding-box sizes (x, y, z)");
    if (node.json().size() != 3)
      node.fail("expected 3 bounding-box sizes (x, y, z), got " + std::to_string(node.json().size()) +
                " (PolyFEM would take a missing size as 0 and flatten the mesh)");
    const std::array<double, 3> d = node.vec3();
    for (int c = 0; c < 3; ++c)
      if (d[c] < 0) node.elements()[c].fail_value("must be >= 0 (a negative size would mirror the mesh)");
    if (d[0] == 0 && d[1] == 0 && d[2] == 0) node.fail("all sizes are 0: the mesh would shrink to a point");
    if (!obstacle)
      for (int c = 0; c < 3; ++c)
        if (d[c] == 0) node.elements()[c].fail_value("a body's sizes must be > 0 (a size of 0 flattens its hexahedra)");
    return d;
  }

  static std::array<double, 9> axis_angle(std::array<double, 3> a, double angle) {
    const double n = std::sqrt(squared_norm3(a.data()));
    for (double& v : a) v /= n;
    // Rodrigues: R = cos θ I + sin θ [a]× + (1 − cos θ) a aᵀ.
    const double c = std::cos(angle), s = std::sin(angle), k = 1 - c;
    return {c + k * a[0] * a[0],        k * a[0] * a[1] - s * a[2], k * a[0] * a[2] + s * a[1],
            k * a[1] * a[0] + s * a[2], c + k * a[1] * a[1],        k * a[1] * a[2] - s * a[0],
            k * a[2] * a[0] - s * a[1], k * a[2] * a[1] + s * a[0], c + k * a[2] * a[2]};
  }

  static std::array<double, 9> multiply(const std::array<double, 9>& A, const std::array<double, 9>& B) {
    std::array<double, 9> C{};
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c)
        for (int k = 0; k < 3; ++k) C[3 * r + c] += A[3 * r + k] * B[3 * k + c];
    return C;
  }

  std::array<double, 9> rotation_matrix(const SceneJsonNode& node, const std::string& mode) {
    const double degree = M_PI / 180;
    if (node.json().is_array() && node.json().empty()) return {1, 0, 0, 0, 1, 0, 0, 0, 1};
    std::vector<double> r;
    if (node.json().is_number()) {
      if (mode.size() != 1 || mode[0] < 'x' || mode[0] > 'z')
        node.fail("a single angle needs rotation_mode \"x\", \"y\" or \"z\"");
      r = {0, 0, 0};
      r[mode[0] - 'x'] = node.number();
    } else {
      for (const SceneJsonNode& item : node.elements()) r.push_back(item.number());
    }
    if (mode == "axis_angle" || mode == "quaternion") {
      if (r.size() != 4) node.fail("rotation_mode \"" + mode + "\" takes 4 numbers, got " + std::to_string(r.size()));
      if (mode == "axis_angle") {
        if (!(r[1] * r[1] + r[2] * r[2] + r[3] * r[3] > 0)) node.fail_value("the rotation axis must be non-zero");
        return axis_angle({r[1], r[2], r[3]}, r[0] * degree);
      }
      // [x, y, z, w] (Eigen's coefficient order), normalised.
      const double n = std::sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2] + r[3] * r[3]);
      if (!(n > 0)) node.fail_value("the quaternion must be non-zero");
      const double x = r[0] / n, y = r[1] / n, z = r[2] / n, w = r[3] / n;
      return {1 - 2 * (y * y + z * z), 2 * (x * y - z * w),     2 * (x * z + y * w),
              2 * (x * y + z * w),     1 - 2 * (x * x + z * z), 2 * (y * z - x * w),
              2 * (x * z - y * w),     2 * (y * z + x * w),     1 - 2 * (x * x + y * y)};
    }
    if (r.size() != 3)
      node.fail("rotation_mode \"" + mode + "\" takes 3 angles (degrees), got " + std::to_string(r.size()));
    if (mode == "rotation_vector") {
      const double angle = std::sqrt(squared_norm3(r.data()));
      if (angle == 0) return {1, 0, 0, 0, 1, 0, 0, 0, 1};
      return axis_angle({r[0], r[1], r[2]}, angle * degree);
    }
    if (mode.empty() || mode.find_first_not_of("xyz") != std::string::npos)
      node.fail("unknown rotation_mode \"" + mode +
                "\" (allowed: a sequence of x, y, z; axis_angle; quaternion; rotation_vector)");
    std::array<double, 9> R{1, 0, 0, 0, 1, 0, 0, 0, 1};
    for (char axis : mode) {
      std::array<double, 3> a{0, 0, 0};
      a[axis - 'x'] = 1;
      R = multiply(axis_angle(a, r[axis - 'x'] * degree), R);
    }
    return R;
  }

  std::vector<FaceSelection> surface_selection(const SceneJsonNode& node) {
    if (node.json().is_number_integer()) return {FaceSelection{node.integer(), std::nullopt}};
    std::vector<FaceSelection> selections;
    for (const SceneJsonNode& item : one_or_many(node)) {
      if (!item.json().is_object()) item.fail("expected an integer id or a {id, box} selection");
      if (has_any(item.json(),
                  {"threshold", "radius", "center", "p1", "p2", "point", "normal", "axis", "position", "file"}))
        item.fail(std::string(kNotModelled) + "dipc reads box selections ({id, box}) and whole-body ids only");
      item.expect_object({"id", "box", "relative", "boundary_only"});
      if (auto relative = item.find("relative"))
        if (relative->boolean())
          relative->fail_value(std::string(kNotModelled) + "give the box in absolute coordinates");
      FaceSelection s;
      s.id = item.required("id").integer();
      const SceneJsonNode box = item.required("box");
      const std::vector<SceneJsonNode> corners = box.elements();
      if (corners.size() != 2) box.fail("expected [[xmin, ymin, zmin], [xmax, ymax, zmax]]");
      const std::array<double, 3> lo = corners[0].vec3(), hi = corners[1].vec3();
      s.box = std::array<double, 6>{lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]};
      selections.push_back(s);
    }
    return selections;
  }

  void geometry(const SceneJsonNode& node, bool contact_enabled) {
    const std::vector<SceneJsonNode> items = one_or_many(node);
    for (std::size_t i = 0; i < items.size(); ++i) {
      const SceneJsonNode& item = items[i];
      item.expect_object({"mesh", "type", "transformation", "volume_selection", "surface_selection", "point_selection",
                          "curve_selection", "is_obstacle", "enabled", "n_refs", "extract", "unit", "advanced", "point",
                          "normal", "height"});
      if (auto enabled = item.find("enabled"); enabled && !enabled->boolean()) {
        note(*enabled, "false: this geometry is skipped, as PolyFEM skips it");
        continue;
      }
      const std::string type = item.find("type") ? item.required("type").string() : "mesh";
      const bool obstacle = item.find("is_obstacle") && item.required("is_obstacle").boolean();
      if (type == "plane" || type == "ground") {
        if (!contact_enabled) item.fail("a plane obstacle needs contact (contact.enabled = true)");
        Plane p;
        if (type == "plane") {
          p.point = item.required("point").vec3();
          const SceneJsonNode normal = item.required("normal");
          const std::array<double, 3> n = normal.vec3();
          const double length = std::sqrt(squared_norm3(n.data()));
          if (!(length > 0)) normal.fail_value("plane normal must be non-zero");
          p.normal = {n[0] / length, n[1] / length, n[2] / length};
        } else {
          // PolyFEM's ground is orthogonal to its fixed gravity (0, −9.81, 0): y is up.
          p.point = {0, item.required("height").number(), 0};
          p.normal = {0, 1, 0};
        }
        scene.contact.planes.push_back(p);
        continue;
      }
      if (type != "mesh")
        item.required("type").fail_value(std::string(kNotModelled) +
                                         "dipc reads \"mesh\", \"plane\" and \"ground\" geometry");
      for (const char* key : {"point_selection", "curve_selection"})
        if (auto s = item.find(key))
          s->fail(std::string(kNotModelled) + "dipc selects surfaces (surface_selection) only");
      if (auto refs = item.find("n_refs"))
        if (refs->integer() != 0)
          refs->fail_value(std::string(kNotModelled) + "refine the mesh before (dipc does not refine meshes)");
      if (auto unit = item.find("unit"))
        if (!unit->string().empty() && unit->string() != "m")
          unit->fail_value(std::string(kNotModelled) + "dipc's lengths are metres");
      if (auto advanced = item.find("advanced")) {
        for (const auto& entry : advanced->json().items()) {
          const SceneJsonNode child = *advanced->find(entry.key());
          if (entry.key() == "normalize_mesh" && child.boolean())
            child.fail_value(std::string(kNotModelled) + "dipc does not rescale meshes");
          if (entry.key() != "normalize_mesh") note(child, "ignored (a meshing option of PolyFEM's)");
        }
      }
      const SceneJsonNode mesh = item.required("mesh");
      const std::string file = resolve_mesh_path(mesh, base_directory);
      const std::string extension = lower(std::filesystem::path(file).extension().string());
      std::array<double, 9> linear{1, 0, 0, 0, 1, 0, 0, 0, 1};
      std::array<double, 3> translation{0, 0, 0};
      std::optional<std::array<double, 3>> dimensions;
      if (auto t = item.find("transformation")) transformation(*t, obstacle, linear, translation, dimensions);
      if (obstacle) {
        if (!contact_enabled) item.fail("an obstacle needs contact (contact.enabled = true)");
        if (extension != ".obj" && extension != ".stl")
          mesh.fail_value(std::string(kNotModelled) + "dipc reads obstacle surfaces from OBJ or STL files");
        Obstacle o;
        o.name = "geometry" + std::to_string(i);
        o.key_path = item.path();
        o.mesh_file = file;
        o.linear = linear;
        o.translation = translation;
        o.dimensions = dimensions;
        std::optional<int> id;
        if (auto s = item.find("surface_selection")) {
          if (!s->json().is_number_integer())
            s->fail("an obstacle's surface_selection must be an integer id (as in PolyFEM)");
          id = s->integer();
        }
        if (auto v = item.find("volume_selection")) note(*v, "ignored (an obstacle has no volume)");
        if (auto e = item.find("extract")) note(*e, "ignored (an obstacle is its surface)");
        scene.contact.obstacles.push_back(o);
        obstacle_id.push_back(id);
        obstacle_key.push_back(item.path());
        continue;
      }
      if (extension != ".msh")
        mesh.fail_value(std::string(kNotModelled) + "a deformable body must be a hexahedral Gmsh MSH mesh "
                                                    "(dipc-voxelize turns a closed OBJ or STL surface into one)");
      if (auto e = item.find("extract"))
        if (e->string() != "volume") e->fail_value(std::string(kNotModelled) + "dipc simulates volumes");
      Body b;
      b.name = "geometry" + std::to_string(i);
      b.mesh_file = file;
      b.linear = linear;
      b.translation = translation;
      b.dimensions = dimensions;
      int volume = 0;
      if (auto v = item.find("volume_selection")) {
        if (v->json().is_number_integer()) {
          volume = v->integer();
        } else if (v->json().is_object() && v->json().size() == 1 && v->json().contains("id_offset")) {
          volume = v->required("id_offset").integer();
          note(*v, "the volume id is id_offset + 0 (dipc does not read element ids from MSH files)");
        } else {
          v->fail(std::string(kNotModelled) + "dipc gives a whole body one volume id: give an integer");
        }
      } else if (scene.materials.size() > 1) {
        note(item, "no volume_selection: volume id 0 (dipc does not read element ids from MSH files)");
      }
      b.material = material_of(volume, item);
      if (auto s = item.find("surface_selection")) b.face_selections = surface_selection(*s);
      scene.bodies.push_back(b);
      volume_id.push_back(volume);
    }
    if (scene.bodies.empty()) node.fail("needs at least one deformable (not is_obstacle) mesh");
  }

  // ---- time ---------------------------------------------------------------------------------
  void time(const SceneJsonNode& node) {
    node.expect_object({"t0", "tend", "dt", "time_steps", "integrator", "quasistatic"});
    if (auto t0 = node.find("t0"))
      if (t0->number() != 0) t0->fail_value(std::string(kNotModelled) + "dipc's runs start at t = 0");
    if (auto integrator = node.find("integrator")) {
      std::string name;
      if (integrator->json().is_string()) {
        name = integrator->string();
      } else {
        integrator->expect_object({"type", "steps", "gamma", "beta"});
        name = integrator->required("type").string();
        if (name == "BDF") {
          const int order = integrator->find("steps") ? integrator->required("steps").integer() : 1;
          name = order == 1 ? "BDF1" : "BDF" + std::to_string(order);
        }
      }
      if (name != "ImplicitEuler" && name != "BDF1")
        integrator->fail_value(std::string(kNotModelled) + "dipc integrates with ImplicitEuler (BDF1) only");
    }
    const auto tend = node.find("tend"), dt = node.find("dt"), steps = node.find("time_steps");
    if ((tend ? 1 : 0) + (dt ? 1 : 0) + (steps ? 1 : 0) < 2) node.fail("give two of tend, dt, time_steps");
    if (dt) {
      scene.dt = dt->number();
      if (!(scene.dt > 0)) dt->fail_value("must be > 0");
    }
    if (steps) {
      scene.steps = steps->integer();
      if (scene.steps < 1) steps->fail_value("must be >= 1");
    }
    if (tend) {
      const double end = tend->number();
      if (!(end > 0)) tend->fail_value("must be > 0");
      if (dt && steps) {
        if (std::abs(scene.dt * scene.steps - end) > 1e-12) node.fail("tend != dt × time_steps");
      } else if (dt) {
        // PolyFEM's rule: ceil(tend / dt) steps of dt (the last may end after tend).
        const double n = std::ceil(end / scene.dt);
        if (!(n < 2147483647.0)) tend->fail_value("needs too many steps of dt = " + format_number(scene.dt));
        scene.steps = static_cast<int>(n);
      } else {
        scene.dt = end / scene.steps;
      }
    }
    if (auto q = node.find("quasistatic")) scene.is_static = q->boolean();
  }

  // ---- prescribed displacements -----------------------------------------------------------
  // u(t) of a Dirichlet condition or obstacle: uniform in space, zero at t = 0.
  Motion displacement_motion(const SceneJsonNode& entry) {
    const SceneJsonNode value = entry.required("value");
    const std::vector<PolyfemExpression> u = expression3(value);
    for (int c = 0; c < 3; ++c)
      if (u[c].uses_position())
        value.elements()[c].fail_value(std::string(kNotModelled) +
                                       "it depends on x, y or z; dipc's displacements here are "
                                       "uniform translations (rotations: dipc's own format, motion type \"rotation\")");
    std::vector<std::array<double, 3>> d(scene.steps + 1);
    double largest = 0;
    for (int k = 0; k <= scene.steps; ++k)
      for (int c = 0; c < 3; ++c) {
        d[k][c] = u[c].evaluate(0, 0, 0, k * scene.dt);
        if (!std::isfinite(d[k][c]))
          value.elements()[c].fail_value("is not finite at t = " + format_number(k * scene.dt));
        largest = std::max(largest, std::abs(d[k][c]));
      }
    Motion m;
    if (largest == 0) return m;  // fixed
    if (std::max({std::abs(d[0][0]), std::abs(d[0][1]), std::abs(d[0][2])}) > 1e-12 * largest)
      value.fail_value(std::string(kNotModelled) +
                       "the displacement at t = 0 is not zero (dipc starts from the rest placement)");
    // u = v t when every sample lies on the line through the first step (to round-off).
    std::array<double, 3> v;
    for (int c = 0; c < 3; ++c) v[c] = d[1][c] / scene.dt;
    bool linear = true;
    for (int k = 0; k <= scene.steps && linear; ++k)
      for (int c = 0; c < 3; ++c) linear = linear && std::abs(d[k][c] - v[c] * k * scene.dt) <= 1e-10 * largest;
    if (linear) {
      m.kind = Motion::Kind::Velocity;
      m.velocity = v;
      return m;
    }
    m.kind = Motion::Kind::Path;
    for (int k = 0; k <= scene.steps; ++k)
      m.path.push_back({k * scene.dt, k == 0 ? 0 : d[k][0], k == 0 ? 0 : d[k][1], k == 0 ? 0 : d[k][2]});
    note(value, "not linear in t: followed as a path through its values at the " + std::to_string(scene.steps) +
                    " step times (where PolyFEM evaluates it), linear in between");
    return m;
  }

  void check_displacement_entry(const SceneJsonNode& entry, bool dirichlet) {
    if (dirichlet)
      entry.expect_object({"id", "value", "dimension", "time_reference", "interpolation"});
    else
      entry.expect_object({"id", "value", "interpolation"});
    if (auto dim = entry.find("dimension"))
      for (const SceneJsonNode& flag : dim->elements())
        if (!flag.boolean())
          flag.fail_value(std::string(kNotModelled) + "dipc prescribes all three components of a node");
    if (auto times = entry.find("time_reference"))
      if (!times->elements().empty())
        times->fail(std::string(kNotModelled) + "write the displacement as an expression of t instead");
    if (auto interpolation = entry.find("interpolation")) {
      for (const SceneJsonNode& i : one_or_many(*interpolation)) {
        if (!i.json().is_object() || i.required("type").string() != "none")
          i.fail(std::string(kNotModelled) +
                 "write the displacement as an expression of t instead of an interpolation");
      }
    }
  }

  void boundary_conditions(const SceneJsonNode& node) {
    node.expect_object({"rhs", "dirichlet_boundary", "neumann_boundary", "pressure_boundary",
                        "normal_aligned_neumann_boundary", "pressure_cavity", "periodic_boundary",
                        "obstacle_displacements"});
    if (auto rhs = node.find("rhs")) {
      if (!(rhs->json().is_array() && rhs->json().empty())) {
        const std::array<double, 3> f = constant3(*rhs, "dipc's body force is uniform gravity");
        scene.gravity = {-f[0], -f[1], -f[2]};  // PolyFEM's energy +∫ ρ rhs·u: the force is −ρ rhs
      }
    }
    for (const char* key :
         {"neumann_boundary", "pressure_boundary", "normal_aligned_neumann_boundary", "pressure_cavity"})
      if (auto n = node.find(key))
        if (!n->json().empty())
          n->fail(std::string(kNotModelled) + "dipc has no traction or pressure boundary conditions");
    if (auto periodic = node.find("periodic_boundary")) {
      const auto enabled = periodic->json().is_object() ? periodic->find("enabled") : std::nullopt;
      if (!enabled || enabled->boolean())
        periodic->fail(std::string(kNotModelled) + "dipc has no periodic boundary conditions");
    }
    // An obstacle takes the motion of the first Dirichlet entry with its id, overridden by the
    // first obstacle_displacements entry with it (GeometryReader.cpp, read_obstacle_geometry).
    std::vector<std::optional<Motion>> from_dirichlet(obstacle_id.size()), from_displacements(obstacle_id.size());
    std::vector<std::string> obstacle_key_path(obstacle_id.size());
    if (auto dirichlet = node.find("dirichlet_boundary")) {
      for (const SceneJsonNode& entry : dirichlet->elements()) {
        if (!entry.json().is_object())
          entry.fail(std::string(kNotModelled) + "Dirichlet values from files are not read");
        check_displacement_entry(entry, true);
        const Motion motion = displacement_motion(entry);
        const SceneJsonNode id_node = entry.required("id");
        for (int id : ids_of(id_node)) {
          bool used = false;
          for (std::size_t b = 0; b < scene.bodies.size(); ++b) {
            for (const FaceSelection& s : scene.bodies[b].face_selections) {
              if (s.id != id) continue;
              DirichletCondition bc;
              static_cast<Motion&>(bc) = motion;
              bc.selection.name = scene.bodies[b].name + ".surface_selection_" + std::to_string(id);
              bc.key_path = entry.path();
              scene.dirichlet.push_back(bc);
              used = true;
              break;
            }
          }
          for (std::size_t o = 0; o < obstacle_id.size(); ++o)
            if (obstacle_id[o] == id) {
              if (!from_dirichlet[o]) from_dirichlet[o] = motion, obstacle_key_path[o] = entry.path();
              used = true;
            }
          if (!used) id_node.fail_value("no geometry's surface_selection has id " + std::to_string(id));
        }
      }
    }
    if (auto displacements = node.find("obstacle_displacements")) {
      for (const SceneJsonNode& entry : displacements->elements()) {
        check_displacement_entry(entry, false);
        const Motion motion = displacement_motion(entry);
        const SceneJsonNode id_node = entry.required("id");
        for (int id : ids_of(id_node)) {
          bool used = false;
          for (std::size_t o = 0; o < obstacle_id.size(); ++o)
            if (obstacle_id[o] == id) {
              if (!from_displacements[o]) from_displacements[o] = motion;
              used = true;
            }
          if (!used) id_node.fail_value("no obstacle's surface_selection has id " + std::to_string(id));
        }
      }
    }
    for (std::size_t o = 0; o < obstacle_id.size(); ++o) {
      if (from_displacements[o])
        scene.contact.obstacles[o].motion = *from_displacements[o];
      else if (from_dirichlet[o])
        scene.contact.obstacles[o].motion = *from_dirichlet[o];
    }
  }

  void initial_conditions(const SceneJsonNode& node) {
    node.expect_object({"solution", "velocity", "acceleration"});
    if (auto solution = node.find("solution"))
      for (const SceneJsonNode& entry : solution->elements()) {
        entry.expect_object({"id", "value"});
        const std::array<double, 3> u = constant3(entry.required("value"),
                                                  "dipc starts every body at its rest placement");
        if (u[0] != 0 || u[1] != 0 || u[2] != 0)
          entry.required("value").fail_value(std::string(kNotModelled) +
                                             "dipc starts every body at its rest placement");
      }
    if (auto velocity = node.find("velocity")) {
      std::set<int> seen;
      for (const SceneJsonNode& entry : velocity->elements()) {
        entry.expect_object({"id", "value"});
        const std::array<double, 3> v = constant3(entry.required("value"), "dipc's initial velocity is one per body");
        const SceneJsonNode id_node = entry.required("id");
        for (int id : ids_of(id_node)) {
          if (!seen.insert(id).second)
            id_node.fail_value("a second initial velocity for volume id " + std::to_string(id));
          bool used = false;
          for (std::size_t b = 0; b < scene.bodies.size(); ++b)
            if (volume_id[b] == id) scene.bodies[b].initial_velocity = v, used = true;
          if (!used) id_node.fail_value("no body has volume id " + std::to_string(id));
        }
      }
    }
    if (auto acceleration = node.find("acceleration"))
      if (!acceleration->json().empty())
        note(*acceleration, "ignored (implicit Euler does not use an initial acceleration)");
  }

  // ---- contact and solver -------------------------------------------------------------------
  void contact(const SceneJsonNode& node) {
    node.expect_object({"enabled", "dhat", "dhat_percentage", "epsv", "friction_coefficient",
                        "use_convergent_formulation", "use_area_weighting", "use_improved_max_operator",
                        "use_physical_barrier", "collision_mesh", "use_gcp_formulation", "alpha_n", "alpha_t",
                        "min_distance_ratio", "use_adaptive_dhat", "periodic", "adhesion"});
    ContactSettings& c = scene.contact;
    if (auto enabled = node.find("enabled")) c.enabled = enabled->boolean();
    c.dhat_relative = false;  // PolyFEM's dhat is a length
    c.dhat = 1e-3;
    if (auto dhat = node.find("dhat")) {
      c.dhat = dhat->number();
      if (!(c.dhat > 0)) dhat->fail_value("must be > 0");
      if (auto p = node.find("dhat_percentage")) note(*p, "ignored (dhat is given)");
    } else if (c.enabled) {
      scene.notes.push_back(source +
                            ": contact.dhat: not given: 1e-3 (PolyFEM's default; PolyFEM would lower it to "
                            "dhat_percentage × the shortest boundary edge where that edge is shorter, dipc does not)");
    }
    if (auto epsv = node.find("epsv")) {
      c.epsv = epsv->number();
      if (!(c.epsv > 0)) epsv->fail_value("must be > 0");
    }
    if (auto mu = node.find("friction_coefficient")) {
      c.friction = mu->number();
      if (c.friction < 0) mu->fail_value("must be >= 0");
    }
    for (const char* key : {"use_convergent_formulation", "use_gcp_formulation", "use_adaptive_dhat", "periodic"})
      if (auto flag = node.find(key))
        if (flag->boolean())
          flag->fail_value(std::string(kNotModelled) + "dipc's barrier is IPC's original one, without this option");
    for (const char* key : {"use_area_weighting", "use_improved_max_operator", "use_physical_barrier", "alpha_n",
                            "alpha_t", "min_distance_ratio"})
      if (auto option = node.find(key)) note(*option, "ignored (it applies only to a formulation that is off)");
    if (auto mesh = node.find("collision_mesh")) {
      const auto enabled = mesh->json().is_object() ? mesh->find("enabled") : std::nullopt;
      if (!enabled || enabled->boolean())
        mesh->fail(std::string(kNotModelled) + "dipc's contact surface is the mesh's boundary");
    }
    if (auto adhesion = node.find("adhesion")) {
      const auto enabled = adhesion->json().is_object() ? adhesion->find("adhesion_enabled") : std::nullopt;
      if (enabled && enabled->boolean()) enabled->fail_value(std::string(kNotModelled) + "dipc has no adhesion");
      note(*adhesion, "ignored (adhesion is off)");
    }
  }

  void solver(const SceneJsonNode& node) {
    if (!node.json().is_object()) node.fail("expected an object");
    for (const auto& entry : node.json().items()) {
      const SceneJsonNode child = *node.find(entry.key());
      if (entry.key() == "contact") {
        for (const auto& option : child.json().items()) {
          const SceneJsonNode o = *child.find(option.key());
          if (option.key() == "barrier_stiffness") {
            if (o.json().is_string()) {
              if (o.string() != "adaptive") o.fail_value("expected \"adaptive\" or a number > 0");
              scene.contact.kappa_adaptive = true;
            } else {
              scene.contact.kappa_adaptive = false;
              scene.contact.kappa = o.number();
              if (!(scene.contact.kappa > 0)) o.fail_value("must be > 0");
            }
          } else if (option.key() == "friction_iterations") {
            const int n = o.integer();
            if (n < 0) o.fail_value(std::string(kNotModelled) + "give a number of lagged friction updates >= 0");
            if (n == 0) {
              scene.contact.friction = 0;
              note(o, "0: friction off (PolyFEM's rule)");
            } else {
              scene.contact.friction_iterations = n;
            }
          } else {
            note(o, "ignored (a solver choice; dipc's own CCD and adaptive barrier stiffness decide it)");
          }
        }
      } else if (entry.key() == "advanced") {
        for (const auto& option : child.json().items()) {
          const SceneJsonNode o = *child.find(option.key());
          if (option.key() == "lump_mass_matrix")
            scene.lumped_mass = o.boolean();
          else
            note(o, "ignored (a solver choice; dipc's numerics are PETSc options)");
        }
      } else if (entry.key() == "rayleigh_damping") {
        if (!child.json().empty()) child.fail(std::string(kNotModelled) + "dipc has no Rayleigh damping");
      } else {
        note(child, "ignored (a solver choice; dipc's numerics are PETSc options, see dipc -help)");
      }
    }
  }

  void space(const SceneJsonNode& node) {
    if (!node.json().is_object()) node.fail("expected an object");
    for (const auto& entry : node.json().items()) {
      const SceneJsonNode child = *node.find(entry.key());
      if (entry.key() == "discr_order") {
        if (!child.json().is_number_integer() || child.integer() != 1)
          child.fail(std::string(kNotModelled) + "dipc's elements are linear (discr_order 1)");
      } else if (entry.key() == "basis_type") {
        if (child.string() != "Lagrange") child.fail_value(std::string(kNotModelled) + "dipc's basis is Lagrange");
      } else if (entry.key() == "use_p_ref" || entry.key() == "remesh") {
        const bool on = child.json().is_boolean() ? child.boolean()
                                                  : child.find("enabled") && child.required("enabled").boolean();
        if (on) child.fail(std::string(kNotModelled) + "dipc does not refine or remesh");
      } else {
        note(child, "ignored (dipc's hexahedra are trilinear with 2×2×2 Gauss points)");
      }
    }
  }

  void units(const SceneJsonNode& node) {
    node.expect_object({"length", "mass", "time", "characteristic_length"});
    const std::map<std::string, std::string> si = {{"length", "m"}, {"mass", "kg"}, {"time", "s"}};
    for (const auto& [key, unit] : si)
      if (auto u = node.find(key))
        if (u->string() != unit) u->fail_value(std::string(kNotModelled) + "dipc's units are m, kg, s");
    if (auto l = node.find("characteristic_length"))
      note(*l, "ignored (dipc's tolerances scale with the scene's size)");
  }
};

}  // namespace

std::string polyfem_marker(const nlohmann::json& d) {
  if (!d.is_object()) return "";
  auto first = [](const nlohmann::json& object, std::initializer_list<const char*> keys) -> std::string {
    if (object.is_object())
      for (const char* key : keys)
        if (object.contains(key)) return key;
    return "";
  };
  std::string key = first(d, {"space", "initial_conditions", "units", "common", "root_path", "tests", "preset_problem",
                              "input"});
  if (!key.empty()) return key;
  for (const char* list : {"geometry", "materials"}) {
    if (!d.contains(list)) continue;
    if (d[list].is_object()) return list;
    if (!d[list].is_array()) continue;
    for (std::size_t i = 0; i < d[list].size(); ++i) {
      key = first(d[list][i], {"transformation", "volume_selection", "surface_selection", "is_obstacle", "type", "id",
                               "enabled", "n_refs"});
      if (!key.empty()) return std::string(list) + "[" + std::to_string(i) + "]." + key;
    }
  }
  const std::pair<const char*, std::vector<const char*>> sections[] = {
      {"time", {"time_steps", "tend", "t0", "quasistatic"}},
      {"boundary_conditions",
       {"rhs", "dirichlet_boundary", "neumann_boundary", "obstacle_displacements", "pressure_boundary"}},
      {"contact", {"friction_coefficient", "dhat_percentage"}}};
  for (const auto& [section, keys] : sections) {
    if (!d.contains(section) || !d[section].is_object()) continue;
    for (const char* k : keys)
      if (d[section].contains(k)) return std::string(section) + "." + k;
  }
  return "";
}

// The scene with its common files merged in, translated.
static Scene translate(const nlohmann::json& document, const std::string& source, const std::string& base_directory) {
  Translator t;
  t.source = source;
  t.base_directory = base_directory;
  t.scene.source = source;
  t.scene.lumped_mass = false;  // PolyFEM's default: the consistent mass matrix
  const SceneJsonNode root(document, "", t.source);
  root.expect_object({"geometry", "materials", "boundary_conditions", "initial_conditions", "time", "contact", "solver",
                      "output", "space", "units", "root_path", "tests", "preset_problem", "input"});
  for (const char* key : {"preset_problem", "input"})
    if (auto n = root.find(key))
      n->fail(std::string(kNotModelled) + "write the scene out in full (preset problems and restarts are not read)");
  if (auto r = root.find("root_path")) t.base_directory = polyfem_root_directory(r->string(), base_directory);
  if (auto u = root.find("units")) t.units(*u);
  if (auto s = root.find("space")) t.space(*s);
  t.time(root.required("time"));
  if (auto c = root.find("contact")) t.contact(*c);
  t.materials(root.required("materials"));
  t.geometry(root.required("geometry"), t.scene.contact.enabled);
  if (auto bc = root.find("boundary_conditions")) t.boundary_conditions(*bc);
  if (auto ic = root.find("initial_conditions")) t.initial_conditions(*ic);
  if (auto s = root.find("solver")) t.solver(*s);
  if (auto o = root.find("output"))
    t.note(*o, "ignored (dipc writes XDMF + HDF5 to its output directory, -dipc_output)");
  if (auto tests = root.find("tests")) t.note(*tests, "ignored (PolyFEM's regression-test data)");
  return t.scene;
}

Scene translate_polyfem_scene(const nlohmann::json& scene_document, const std::string& source,
                              const std::string& base_directory) {
  std::vector<std::string> common_files;
  const nlohmann::json document = merge_polyfem_common(scene_document, source, base_directory, &common_files);
  if (common_files.empty()) return translate(document, source, base_directory);
  // A key path in a message may name a key that came from the common file.
  std::string files;
  for (const std::string& f : common_files) files += (files.empty() ? "" : ", ") + f;
  try {
    Scene scene = translate(document, source, base_directory);
    scene.notes.insert(scene.notes.begin(), source + ": common: merged: the scene's keys over " + files);
    return scene;
  } catch (const SceneError& e) {
    const std::string file = common_files.size() == 1 ? "file " : "files ";
    throw SceneError(std::string(e.what()) + " (in the scene merged over its common " + file + files + ")");
  }
}

}  // namespace dipc
