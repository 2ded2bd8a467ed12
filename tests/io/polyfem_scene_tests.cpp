// PolyFEM's JSON format read into dipc's Scene (io/polyfem_scene.cpp): the expressions, each
// key's meaning and default (transformation order and rotation modes, rhs sign, absolute dhat,
// rho = 1, consistent mass, ceil(tend / dt) steps, materials by volume id, motions from
// displacement expressions, transformation.dimensions and its factors), and a table of scenes
// dipc cannot model, each refused with a message naming the key path. Nothing here reads a
// mesh: the translation does not.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "io/bounding_box_scale.hpp"
#include "io/polyfem_expression.hpp"
#include "io/polyfem_scene.hpp"
#include "io/scene.hpp"

namespace dipc {
namespace {

TEST(PolyfemExpression, EvaluatesArithmeticOfXYZT) {
  EXPECT_DOUBLE_EQ(PolyfemExpression("1 + 2 * 3").evaluate(0, 0, 0, 0), 7);
  EXPECT_DOUBLE_EQ(PolyfemExpression("-2^2").evaluate(0, 0, 0, 0), -4);
  EXPECT_DOUBLE_EQ(PolyfemExpression("2^-1").evaluate(0, 0, 0, 0), 0.5);
  EXPECT_DOUBLE_EQ(PolyfemExpression("(1 - 2) - 3").evaluate(0, 0, 0, 0), -4);
  EXPECT_DOUBLE_EQ(PolyfemExpression("8 / 4 / 2").evaluate(0, 0, 0, 0), 1);
  EXPECT_DOUBLE_EQ(PolyfemExpression("x*y - z + t").evaluate(2, 3, 1, 0.5), 5.5);
  EXPECT_NEAR(PolyfemExpression("sin(pi*t/2)^2 + sqrt(abs(-4)) + exp(log(3))").evaluate(0, 0, 0, 1), 6, 1e-14);
  EXPECT_DOUBLE_EQ(PolyfemExpression("1.5e-3").evaluate(0, 0, 0, 0), 1.5e-3);
  const PolyfemExpression e("0.1 * t");
  EXPECT_TRUE(e.uses_time());
  EXPECT_FALSE(e.uses_position());
  EXPECT_TRUE(PolyfemExpression("cos(z)").uses_position());
}

TEST(PolyfemExpression, RefusesWhatItCannotRead) {
  for (const char* bad : {"", "1 +", "2 ^ 3 ^ 2", "foo(t)", "sin t", "(1", "1 2", "data.txt", "u"}) {
    EXPECT_THROW(PolyfemExpression{bad}, std::invalid_argument) << bad;
  }
  try {
    PolyfemExpression("1 + w");
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("at character 5: unknown name \"w\""), std::string::npos) << e.what();
  }
}

// A one-body scene with `extra` root keys (after a comma) and the given geometry entry.
std::string scene(const std::string& geometry, const std::string& extra = "") {
  return R"({"geometry": [)" + geometry + R"(],
    "materials": [{"type": "NeoHookean", "E": 1e6, "nu": 0.4}],
    "time": {"dt": 0.01, "time_steps": 4})" +
         (extra.empty() ? "" : ", " + extra) + "}";
}

// The one-body scene with more `time` keys.
std::string timed(const std::string& time_keys) {
  return R"({"geometry": [{"mesh": "a.msh"}], "materials": [{"type": "NeoHookean", "E": 1e6, "nu": 0.4}],
    "time": {"dt": 0.01, "time_steps": 4, )" +
         time_keys + "}}";
}

Scene read(const std::string& text) { return parse_scene_text(text, "pf.json", "/base"); }

TEST(PolyfemScene, DefaultsAndConventions) {
  const Scene s = read(scene(R"({"mesh": "a.msh"})", R"("boundary_conditions": {"rhs": [0, 9.81, 0]},
      "contact": {"enabled": true, "dhat": 0.002, "friction_coefficient": 0.3})"));
  ASSERT_EQ(s.bodies.size(), 1u);
  EXPECT_EQ(s.bodies[0].mesh_file, "/base/a.msh");
  EXPECT_EQ(s.materials[0].rho, 1);  // PolyFEM's default density
  EXPECT_FALSE(s.lumped_mass);       // consistent mass unless lump_mass_matrix
  EXPECT_EQ(s.gravity, (std::array<double, 3>{0, -9.81, 0}));
  EXPECT_TRUE(s.contact.enabled);
  EXPECT_FALSE(s.contact.dhat_relative);
  EXPECT_EQ(s.contact.dhat, 0.002);
  EXPECT_EQ(s.contact.friction, 0.3);
  EXPECT_FALSE(s.is_static);
  EXPECT_EQ(s.steps, 4);
  EXPECT_TRUE(s.notes.empty());
  // dhat not given: PolyFEM's 1e-3, with a note on the rule dipc does not follow.
  const Scene d = read(scene(R"({"mesh": "a.msh"})", R"("contact": {"enabled": true})"));
  EXPECT_EQ(d.contact.dhat, 1e-3);
  ASSERT_EQ(d.notes.size(), 1u);
  EXPECT_NE(d.notes[0].find("contact.dhat: not given"), std::string::npos);
}

TEST(PolyfemScene, TimeFollowsPolyfemsRules) {
  auto time = [](const std::string& t) {
    return read(R"({"geometry": {"mesh": "a.msh"}, "materials": {"type": "NeoHookean", "E": 1, "nu": 0}, "time": )" +
                t + "}");
  };
  EXPECT_EQ(time(R"({"tend": 0.1, "dt": 0.03})").steps, 4);  // ceil(tend / dt)
  const Scene n = time(R"({"tend": 0.1, "time_steps": 4, "integrator": "BDF1"})");
  EXPECT_DOUBLE_EQ(n.dt, 0.025);
  EXPECT_TRUE(time(R"({"dt": 0.1, "time_steps": 2, "quasistatic": true})").is_static);
}

// Every rotation mode PolyFEM takes gives the same 90° turn about z; scale comes first.
TEST(PolyfemScene, TransformationScalesThenRotatesThenTranslates) {
  for (const std::string rotation :
       {R"("rotation": [0, 0, 90])", R"("rotation": [0, 0, 90], "rotation_mode": "zyx")",
        R"("rotation": 90, "rotation_mode": "z")", R"("rotation": [90, 0, 0, 2], "rotation_mode": "axis_angle")",
        R"("rotation": [0, 0, 90], "rotation_mode": "rotation_vector")",
        R"("rotation": [0, 0, 0.70710678118654757, 0.70710678118654757], "rotation_mode": "quaternion")"}) {
    const Scene s = read(scene(R"({"mesh": "a.msh", "transformation": {"scale": [2, 3, 4], )" + rotation +
                               R"(, "translation": [1, 2, 3]}})"));
    const std::array<double, 9> expected{0, -3, 0, 2, 0, 0, 0, 0, 4};  // R_z(90°) · diag(2, 3, 4)
    for (int k = 0; k < 9; ++k) EXPECT_NEAR(s.bodies[0].linear[k], expected[k], 1e-15) << rotation << " entry " << k;
    EXPECT_EQ(s.bodies[0].translation, (std::array<double, 3>{1, 2, 3}));
  }
  // Euler angles "xyz" rotate about x first: R = R_z R_y R_x.
  const Scene s = read(scene(R"({"mesh": "a.msh", "transformation": {"rotation": [90, 90, 0]}})"));
  const std::array<double, 9> expected{0, 1, 0, 0, 0, -1, -1, 0, 0};  // R_y(90°) R_x(90°)
  for (int k = 0; k < 9; ++k) EXPECT_NEAR(s.bodies[0].linear[k], expected[k], 1e-15) << k;
}

// transformation.dimensions: a list replaces `scale` (noted) and is kept for the app, which
// knows the mesh's bounding box; the rotation and translation still apply after it. A number
// there is ignored, as PolyFEM ignores it, and `scale` applies.
TEST(PolyfemScene, DimensionsReplaceScale) {
  const Scene s = read(scene(
      R"({"mesh": "a.msh", "transformation": {"dimensions": [2, 3, 4], "scale": 7, "rotation": [0, 0, 90],
          "translation": [1, 2, 3]}},
        {"mesh": "plane.obj", "is_obstacle": true, "transformation": {"dimensions": [3, 0, 3]}})",
      R"("contact": {"enabled": true, "dhat": 0.001})"));
  ASSERT_EQ(s.bodies.size(), 1u);
  ASSERT_TRUE(s.bodies[0].dimensions);
  EXPECT_EQ(*s.bodies[0].dimensions, (std::array<double, 3>{2, 3, 4}));
  const std::array<double, 9> rotation{0, -1, 0, 1, 0, 0, 0, 0, 1};  // R_z(90°), no scale
  for (int k = 0; k < 9; ++k) EXPECT_NEAR(s.bodies[0].linear[k], rotation[k], 1e-15) << k;
  EXPECT_EQ(s.bodies[0].scale, 1);
  EXPECT_EQ(s.bodies[0].translation, (std::array<double, 3>{1, 2, 3}));
  ASSERT_EQ(s.contact.obstacles.size(), 1u);
  ASSERT_TRUE(s.contact.obstacles[0].dimensions);
  EXPECT_EQ(*s.contact.obstacles[0].dimensions, (std::array<double, 3>{3, 0, 3}));
  EXPECT_EQ(s.contact.obstacles[0].linear, (std::array<double, 9>{1, 0, 0, 0, 1, 0, 0, 0, 1}));
  ASSERT_EQ(s.notes.size(), 1u);
  EXPECT_NE(s.notes[0].find("geometry[0].transformation.scale: ignored: dimensions is given"), std::string::npos)
      << s.notes[0];

  const Scene n = read(scene(R"({"mesh": "a.msh", "transformation": {"dimensions": 5, "scale": 2}})"));
  EXPECT_FALSE(n.bodies[0].dimensions);
  EXPECT_EQ(n.bodies[0].linear, (std::array<double, 9>{2, 0, 0, 0, 2, 0, 0, 0, 2}));
  ASSERT_EQ(n.notes.size(), 1u);
  EXPECT_NE(n.notes[0].find("geometry[0].transformation.dimensions: a number: ignored"), std::string::npos)
      << n.notes[0];
}

// The factors of `dimensions` (PolyFEM's construct_affine_transformation): size / extent per
// axis, an axis of zero extent counting as extent 1, so a flat plane given 0 there keeps its
// points at coordinate 0 on it.
TEST(BoundingBoxScale, FactorsGiveTheBoxTheSizes) {
  const std::vector<std::array<double, 3>> box{{-1, 2, 0}, {3, 2.5, 0.25}, {0, 4, 0.5}};  // extents 4, 2, 0.5
  EXPECT_EQ(bounding_box_extent(box), (std::array<double, 3>{4, 2, 0.5}));
  EXPECT_EQ(dimension_factors(std::nullopt, box), (std::array<double, 3>{1, 1, 1}));
  EXPECT_EQ(dimension_factors(std::array<double, 3>{2, 1, 2}, box), (std::array<double, 3>{0.5, 0.5, 4}));
  // PolyFEM's plane.obj (10 × 0 × 10 at y = 0) with "dimensions": [3, 0, 3]: 3 × 3, still flat.
  const std::vector<std::array<double, 3>> plane{{-5, 0, 5}, {5, 0, 5}, {-5, 0, -5}, {5, 0, -5}};
  EXPECT_EQ(dimension_factors(std::array<double, 3>{3, 0, 3}, plane), (std::array<double, 3>{0.3, 0, 0.3}));
  // A flat axis given a non-zero size takes it as the factor (extent counted as 1).
  EXPECT_EQ(dimension_factors(std::array<double, 3>{3, 2, 3}, plane), (std::array<double, 3>{0.3, 2, 0.3}));
  // 0 along an axis where the points extend would flatten the mesh: refused, naming the axis.
  try {
    dimension_factors(std::array<double, 3>{3, 0, 3}, box);
    FAIL() << "flattening accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("0 along y, where the mesh extends 2"), std::string::npos) << e.what();
  }
}

TEST(PolyfemScene, MaterialsByVolumeId) {
  const Scene s = read(R"({"geometry": [{"mesh": "a.msh", "volume_selection": 7}, {"mesh": "b.msh"}],
    "materials": [{"type": "NeoHookean", "id": [3, 7], "E": 2e6, "nu": 0.3, "rho": 900},
                  {"type": "NeoHookean", "E": 1e6, "nu": 0.2}],
    "initial_conditions": {"velocity": [{"id": 7, "value": [1, "2", "-3"]}]},
    "time": {"dt": 0.01, "time_steps": 1}})");
  ASSERT_EQ(s.bodies.size(), 2u);
  EXPECT_EQ(s.bodies[0].material, 0u);
  EXPECT_EQ(s.bodies[1].material, 1u);  // no volume_selection: id 0, the second material's default id
  EXPECT_EQ(s.materials[0].rho, 900);
  EXPECT_EQ(s.bodies[0].initial_velocity, (std::array<double, 3>{1, 2, -3}));
  EXPECT_EQ(s.bodies[1].initial_velocity, (std::array<double, 3>{0, 0, 0}));
}

TEST(PolyfemScene, DisplacementsBecomeMotions) {
  const Scene s = read(scene(
      R"({"mesh": "a.msh", "surface_selection": [{"id": 1, "box": [[0, 0, 0], [1, 1, 0]]}, {"id": 2, "box": [[0, 0, 1], [1, 1, 1]]}, {"id": 3, "box": [[0, 0, 0], [0, 1, 1]]}]},
        {"mesh": "o.obj", "is_obstacle": true, "surface_selection": 4})",
      R"("contact": {"enabled": true, "dhat": 1e-3},
      "boundary_conditions": {"dirichlet_boundary": [{"id": 1, "value": [0, 0, 0]}, {"id": [2, 4], "value": ["0.5*t", 0, "-t"]},
                                                     {"id": 3, "value": ["t^2", 0, 0]}],
                              "obstacle_displacements": [{"id": 4, "value": [0, "2*t", 0]}]})"));
  ASSERT_EQ(s.dirichlet.size(), 3u);
  EXPECT_EQ(s.dirichlet[0].kind, Motion::Kind::Fixed);
  EXPECT_EQ(s.dirichlet[0].selection.name, "geometry0.surface_selection_1");
  EXPECT_EQ(s.dirichlet[1].kind, Motion::Kind::Velocity);
  EXPECT_EQ(s.dirichlet[1].velocity, (std::array<double, 3>{0.5, 0, -1}));
  EXPECT_EQ(s.dirichlet[2].kind, Motion::Kind::Path);  // sampled at the 4 step times
  ASSERT_EQ(s.dirichlet[2].path.size(), 5u);
  EXPECT_NEAR(s.dirichlet[2].path[3][0], 0.03, 1e-17);
  EXPECT_NEAR(s.dirichlet[2].path[3][1], 9e-4, 1e-17);
  ASSERT_EQ(s.bodies[0].face_selections.size(), 3u);
  EXPECT_EQ(s.bodies[0].face_selections[1].id, 2);
  // The obstacle's own displacement wins over the Dirichlet entry that also names its id.
  ASSERT_EQ(s.contact.obstacles.size(), 1u);
  EXPECT_EQ(s.contact.obstacles[0].motion.kind, Motion::Kind::Velocity);
  EXPECT_EQ(s.contact.obstacles[0].motion.velocity, (std::array<double, 3>{0, 2, 0}));
}

TEST(PolyfemScene, PlanesAndGround) {
  const Scene s = read(scene(R"({"mesh": "a.msh"}, {"type": "plane", "point": [0, 0, -1], "normal": [0, 0, 2]},
                               {"type": "ground", "height": -0.5})",
                             R"("contact": {"enabled": true, "dhat": 1e-3})"));
  ASSERT_EQ(s.contact.planes.size(), 2u);
  EXPECT_EQ(s.contact.planes[0].normal, (std::array<double, 3>{0, 0, 1}));
  EXPECT_EQ(s.contact.planes[1].point, (std::array<double, 3>{0, -0.5, 0}));  // PolyFEM's ground: y up
  EXPECT_EQ(s.contact.planes[1].normal, (std::array<double, 3>{0, 1, 0}));
}

TEST(PolyfemScene, DipcsOwnFormatIsNotTakenForPolyfems) {
  const Scene s = read(R"({"materials": [{"E": 1e6}], "geometry": [{"box": {"size": [1, 1, 1]}}],
                           "time": {"dt": 0.1, "steps": 1}})");
  EXPECT_TRUE(s.notes.empty());
  EXPECT_TRUE(s.lumped_mass);
}

// A dipc scene with a PolyFEM key (a typo) is read as PolyFEM's, and its error says why.
TEST(PolyfemScene, ErrorsSayWhyTheFileWasReadAsPolyfems) {
  try {
    read(R"({"materials": [{"E": 1e6}], "geometry": [{"box": {"size": [1, 1, 1]}}], "time": {"dt": 0.1, "tend": 1}})");
    FAIL();
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("[read in PolyFEM's format: it has time.tend]"), std::string::npos)
        << e.what();
  }
  EXPECT_EQ(polyfem_marker(nlohmann::json::parse(R"({"geometry": [{"mesh": "a.msh", "is_obstacle": true}]})")),
            "geometry[0].is_obstacle");
  EXPECT_EQ(polyfem_marker(
                nlohmann::json::parse(R"({"geometry": [{"mesh": "a.msh"}], "time": {"dt": 1, "steps": 2}})")),
            "");
}

struct Refused {
  const char* name;
  std::string text;
  std::vector<std::string> expected;  // substrings of the message
};

class PolyfemRefusals : public ::testing::TestWithParam<Refused> {};

TEST_P(PolyfemRefusals, NameTheKey) {
  const Refused& r = GetParam();
  try {
    read(r.text);
    FAIL() << r.name << " was accepted";
  } catch (const SceneError& e) {
    for (const std::string& s : r.expected) EXPECT_NE(std::string(e.what()).find(s), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).rfind("pf.json: ", 0), 0u) << e.what();
  }
}

const std::string mesh = R"({"mesh": "a.msh"})";
const std::string faces = R"({"mesh": "a.msh", "surface_selection": 1})";

INSTANTIATE_TEST_SUITE_P(
    Table, PolyfemRefusals,
    ::testing::Values(
        Refused{
            "other_material",
            R"({"geometry": {"mesh": "a.msh"}, "materials": {"type": "LinearElasticity", "E": 1, "nu": 0.3}, "time": {"dt": 1, "time_steps": 1}})",
            {"materials.type = \"LinearElasticity\"", "cannot model", "NeoHookean"}},
        Refused{
            "damping",
            R"({"geometry": {"mesh": "a.msh"}, "materials": {"type": "NeoHookean", "E": 1, "nu": 0.3, "phi": 2}, "time": {"dt": 1, "time_steps": 1}})",
            {"materials.phi", "damping"}},
        Refused{
            "expression_material",
            R"({"geometry": {"mesh": "a.msh"}, "materials": {"type": "NeoHookean", "E": "1e6*x", "nu": 0.3}, "time": {"dt": 1, "time_steps": 1}})",
            {"materials.E", "constant material parameters"}},
        Refused{"newmark", timed(R"("integrator": "ImplicitNewmark")"), {"time.integrator", "ImplicitEuler"}},
        Refused{"bdf2", timed(R"("integrator": {"type": "BDF", "steps": 2})"), {"time.integrator", "ImplicitEuler"}},
        Refused{"t0", timed(R"("t0": 1)"), {"time.t0", "t = 0"}},
        Refused{"no_time",
                R"({"geometry": {"mesh": "a.msh"}, "materials": {"type": "NeoHookean", "E": 1, "nu": 0.3}})",
                {"time", "missing"}},
        Refused{
            "one_time_key",
            R"({"geometry": {"mesh": "a.msh"}, "materials": {"type": "NeoHookean", "E": 1, "nu": 0.3}, "time": {"dt": 1}})",
            {"time: give two of"}},
        Refused{"tet_body",
                scene(R"({"mesh": "bunny.obj"})"),
                {"geometry[0].mesh", "hexahedral Gmsh MSH", "dipc-voxelize"}},
        Refused{"refined", scene(R"({"mesh": "a.msh", "n_refs": 1})"), {"geometry[0].n_refs", "refine"}},
        Refused{"sphere_selection",
                scene(R"({"mesh": "a.msh", "surface_selection": [{"id": 1, "center": [0, 0, 0], "radius": 1}]})"),
                {"geometry[0].surface_selection[0]", "box selections"}},
        Refused{
            "relative_box",
            scene(
                R"({"mesh": "a.msh", "surface_selection": [{"id": 1, "box": [[0, 0, 0], [1, 1, 1]], "relative": true}]})"),
            {"geometry[0].surface_selection[0].relative", "absolute"}},
        Refused{"dimensions_two",
                scene(R"({"mesh": "a.msh", "transformation": {"dimensions": [1, 1]}})"),
                {"geometry[0].transformation.dimensions: expected 3 bounding-box sizes", "got 2"}},
        Refused{"dimensions_negative",
                scene(R"({"mesh": "a.msh", "transformation": {"dimensions": [1, -1, 1]}})"),
                {"geometry[0].transformation.dimensions[1] = -1", ">= 0", "mirror"}},
        Refused{"dimensions_zero_body",
                scene(R"({"mesh": "a.msh", "transformation": {"dimensions": [3, 0, 3]}})"),
                {"geometry[0].transformation.dimensions[1] = 0", "a body's sizes must be > 0"}},
        Refused{"dimensions_all_zero",
                scene(mesh + R"(, {"mesh": "p.obj", "is_obstacle": true, "transformation": {"dimensions": [0, 0, 0]}})",
                      R"("contact": {"enabled": true})"),
                {"geometry[1].transformation.dimensions: all sizes are 0"}},
        Refused{"dimensions_text",
                scene(R"({"mesh": "a.msh", "transformation": {"dimensions": "1 1 1"}})"),
                {"geometry[0].transformation.dimensions: expected a list"}},
        Refused{"dimensions_huge",
                scene(R"({"mesh": "a.msh", "transformation": {"dimensions": [1, 1e400, 1]}})"),
                {"geometry[0].transformation.dimensions[1]"}},
        Refused{"point_selection",
                scene(R"({"mesh": "a.msh", "point_selection": 3})"),
                {"geometry[0].point_selection"}},
        Refused{"volume_selection_boxes",
                scene(R"({"mesh": "a.msh", "volume_selection": [{"id": 1, "box": [[0, 0, 0], [1, 1, 1]]}]})"),
                {"geometry[0].volume_selection", "integer"}},
        Refused{"obstacle_without_contact",
                scene(mesh + R"(, {"mesh": "f.obj", "is_obstacle": true})"),
                {"geometry[1]", "contact.enabled"}},
        Refused{"obstacle_msh",
                scene(mesh + R"(, {"mesh": "f.msh", "is_obstacle": true})", R"("contact": {"enabled": true})"),
                {"geometry[1].mesh", "OBJ or STL"}},
        Refused{"neumann",
                scene(faces, R"("boundary_conditions": {"neumann_boundary": [{"id": 1, "value": [0, 0, 1]}]})"),
                {"boundary_conditions.neumann_boundary", "traction"}},
        Refused{"pressure",
                scene(faces, R"("boundary_conditions": {"pressure_boundary": [{"id": 1, "value": 5}]})"),
                {"boundary_conditions.pressure_boundary"}},
        Refused{"rotating_dirichlet",
                scene(faces,
                      R"("boundary_conditions": {"dirichlet_boundary": [{"id": 1, "value": ["x*cos(t) - x", 0, 0]}]})"),
                {"boundary_conditions.dirichlet_boundary[0].value[0]", "x, y or z"}},
        Refused{"jump_dirichlet",
                scene(faces, R"("boundary_conditions": {"dirichlet_boundary": [{"id": 1, "value": [0.1, 0, 0]}]})"),
                {"boundary_conditions.dirichlet_boundary[0].value", "t = 0 is not zero"}},
        Refused{
            "partial_dirichlet",
            scene(
                faces,
                R"("boundary_conditions": {"dirichlet_boundary": [{"id": 1, "value": [0, 0, 0], "dimension": [true, false, true]}]})"),
            {"boundary_conditions.dirichlet_boundary[0].dimension[1]", "all three components"}},
        Refused{"unknown_id",
                scene(faces, R"("boundary_conditions": {"dirichlet_boundary": [{"id": 9, "value": [0, 0, 0]}]})"),
                {"boundary_conditions.dirichlet_boundary[0].id = 9", "surface_selection"}},
        Refused{
            "interpolated",
            scene(
                faces,
                R"("boundary_conditions": {"dirichlet_boundary": [{"id": 1, "value": ["t", 0, 0], "interpolation": {"type": "linear_ramp", "to": 1}}]})"),
            {"boundary_conditions.dirichlet_boundary[0].interpolation", "expression of t"}},
        Refused{"rhs_field",
                scene(mesh, R"("boundary_conditions": {"rhs": [0, "9.81*y", 0]})"),
                {"boundary_conditions.rhs[1]", "uniform gravity"}},
        Refused{"initial_displacement",
                scene(mesh, R"("initial_conditions": {"solution": [{"id": 0, "value": [0.1, 0, 0]}]})"),
                {"initial_conditions.solution[0].value", "rest placement"}},
        Refused{"spinning_start",
                scene(mesh, R"("initial_conditions": {"velocity": [{"id": 0, "value": ["-y", "x", 0]}]})"),
                {"initial_conditions.velocity[0].value[0]"}},
        Refused{"convergent_ipc",
                scene(mesh, R"("contact": {"enabled": true, "use_convergent_formulation": true})"),
                {"contact.use_convergent_formulation"}},
        Refused{"adhesion",
                scene(mesh, R"("contact": {"enabled": true, "adhesion": {"adhesion_enabled": true}})"),
                {"contact.adhesion.adhesion_enabled"}},
        Refused{"rayleigh",
                scene(mesh, R"("solver": {"rayleigh_damping": [{"form": "elasticity", "stiffness": 1}]})"),
                {"solver.rayleigh_damping", "Rayleigh"}},
        Refused{"quadratic", scene(mesh, R"("space": {"discr_order": 2})"), {"space.discr_order", "linear"}},
        Refused{"units", scene(mesh, R"("units": {"length": "mm"})"), {"units.length", "m, kg, s"}},
        Refused{"common_missing",
                scene(mesh, R"("common": "base.json")"),
                {"common = \"base.json\": /base/base.json: cannot open"}},
        Refused{"unknown_root_key", scene(mesh, R"("lagrange": 1)"), {"lagrange: unknown key"}}),
    [](const auto& info) { return std::string(info.param.name); });

}  // namespace
}  // namespace dipc
