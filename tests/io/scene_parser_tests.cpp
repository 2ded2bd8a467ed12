// Scene parser tests: every kind of bad input is rejected with its own message naming the
// file and key path; good scenes give the right values, defaults included.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "io/default_scene.hpp"
#include "io/scene.hpp"

namespace dipc {
namespace {

using json = nlohmann::json;

// A valid scene that each bad case breaks in one place.
json base_scene() {
  return json::parse(R"({
    "materials": [{"name": "rubber", "E": 1e6, "nu": 0.4, "rho": 1000}],
    "geometry": [{"name": "beam", "box": {"size": [1, 0.1, 0.1], "resolution": [4, 1, 1]},
                  "material": "rubber"}],
    "boundary_conditions": {
      "gravity": [0, 0, -9.81],
      "dirichlet": [
        {"selection": "beam.xmin", "type": "fixed"},
        {"selection": {"box": [[0.9, -1, -1], [2, 1, 1]]}, "type": "velocity", "velocity": [0, 0, 0.1]},
        {"selection": "beam.xmax", "type": "rotation", "axis": [1, 0, 0], "angular_velocity": 1}
      ]
    },
    "time": {"dt": 0.01, "steps": 10}
  })");
}

Scene parse(const json& scene) { return parse_scene_text(scene.dump(), "scene.json", "/base"); }

TEST(SceneParser, BaseSceneIsValid) { EXPECT_NO_THROW(parse(base_scene())); }

struct BadScene {
  std::string name;
  std::function<std::string()> text;     // the scene file's text
  std::vector<std::string> expected;    // substrings of the error message
};

std::string edited(const std::function<void(json&)>& edit) {
  json scene = base_scene();
  edit(scene);
  return scene.dump(2);
}

// Replaces the first occurrence of `from` in the base scene's text (for inputs that a json
// object cannot hold: syntax errors, overflowing literals, repeated keys).
std::string raw(const std::string& from, const std::string& to) {
  std::string text = base_scene().dump(2);
  const auto at = text.find(from);
  if (at == std::string::npos) throw std::logic_error("raw(): '" + from + "' not in the base scene");
  return text.replace(at, from.size(), to);
}

std::vector<BadScene> bad_scenes() {
  return {
      {"BadJson", [] { return std::string("{\n  \"materials\": [,]\n}"); },
       {"scene.json: invalid JSON: parse error at line 2, column 17"}},
      {"NotAnObject", [] { return std::string("[1, 2]"); }, {"scene.json: expected an object, got array"}},
      {"UnknownTopLevelKey", [] { return edited([](json& s) { s["meterials"] = json::array(); }); },
       {"scene.json: meterials: unknown key (allowed: materials, geometry, boundary_conditions, time"}},
      {"UnknownNestedKey", [] { return edited([](json& s) { s["geometry"][0]["box"]["sise"] = 1; }); },
       {"scene.json: geometry[0].box.sise: unknown key (allowed: size, resolution, origin)"}},
      {"KeyOfAnotherBcType", [] { return edited([](json& s) { s["boundary_conditions"]["dirichlet"][0]["velocity"] = {0, 0, 1}; }); },
       {"boundary_conditions.dirichlet[0].velocity: unknown key (allowed for type \"fixed\": selection, type)"}},
      {"DuplicateKey", [] { return raw("\"E\": 1000000.0", "\"E\": 1000000.0, \"E\": 2"); },
       {"scene.json: materials[0].E: duplicate key"}},
      {"WrongType", [] { return edited([](json& s) { s["time"]["dt"] = "0.01"; }); },
       {"scene.json: time.dt: expected a number, got string \"0.01\""}},
      {"WrongTypeDeep", [] { return edited([](json& s) { s["boundary_conditions"]["dirichlet"][1]["velocity"][2] = "up"; }); },
       {"scene.json: boundary_conditions.dirichlet[1].velocity[2]: expected a number, got string"}},
      {"WrongLength", [] { return edited([](json& s) { s["boundary_conditions"]["gravity"] = {0, -9.81}; }); },
       {"scene.json: boundary_conditions.gravity: expected an array of 3 numbers, got 2"}},
      {"NuHalf", [] { return edited([](json& s) { s["materials"][0]["nu"] = 0.5; }); },
       {"scene.json: materials[0].nu = 0.5: must be in (-1, 0.5)"}},
      {"NuMinusOne", [] { return edited([](json& s) { s["materials"][0]["nu"] = -1; }); },
       {"scene.json: materials[0].nu = -1: must be in (-1, 0.5)"}},
      {"EZero", [] { return edited([](json& s) { s["materials"][0]["E"] = 0; }); }, {"scene.json: materials[0].E = 0: must be > 0"}},
      {"RhoNegative", [] { return edited([](json& s) { s["materials"][0]["rho"] = -5; }); },
       {"scene.json: materials[0].rho = -5: must be > 0"}},
      {"DtZero", [] { return edited([](json& s) { s["time"]["dt"] = 0; }); }, {"scene.json: time.dt = 0: must be > 0"}},
      {"Overflow", [] { return raw("-9.81", "1e999"); },
       {"scene.json: boundary_conditions.gravity[2]: number overflow parsing '1e999'", "must be finite"}},
      {"EmptyMaterials", [] { return edited([](json& s) { s["materials"] = json::array(); }); },
       {"scene.json: materials: must list at least one material"}},
      {"DuplicateMaterial", [] { return edited([](json& s) { s["materials"].push_back({{"name", "rubber"}}); }); },
       {"scene.json: materials[1].name = \"rubber\": duplicate material name (also materials[0].name)"}},
      {"UnknownMaterial", [] { return edited([](json& s) { s["geometry"][0]["material"] = "steel"; }); },
       {"scene.json: geometry[0].material = \"steel\": unknown material (known: rubber)"}},
      {"MaterialIndexOutOfRange", [] { return edited([](json& s) { s["geometry"][0]["material"] = 1; }); },
       {"scene.json: geometry[0].material = 1: material index must be in [0, 1)"}},
      {"MaterialMissingWithTwo", [] { return edited([](json& s) {
         s["materials"].push_back({{"name", "steel"}});
         s["geometry"][0].erase("material");
       }); },
       {"scene.json: geometry[0]: \"material\" is required when the scene has 2 materials"}},
      {"BoxAndMesh", [] { return edited([](json& s) { s["geometry"][0]["mesh"] = "a.msh"; }); },
       {"scene.json: geometry[0]: give either \"box\" or \"mesh\", not both"}},
      {"NeitherBoxNorMesh", [] { return edited([](json& s) { s["geometry"][0].erase("box"); }); },
       {"scene.json: geometry[0]: needs a \"box\" or a \"mesh\""}},
      {"DuplicateBody", [] { return edited([](json& s) { s["geometry"].push_back(s["geometry"][0]); }); },
       {"scene.json: geometry[1]: duplicate body name \"beam\" (also geometry[0])"}},
      {"BodyNameWithDot", [] { return edited([](json& s) { s["geometry"][0]["name"] = "a.b"; }); },
       {"scene.json: geometry[0].name = \"a.b\": must not contain '.'"}},
      {"BoxSizeZero", [] { return edited([](json& s) { s["geometry"][0]["box"]["size"][1] = 0; }); },
       {"scene.json: geometry[0].box.size[1] = 0: must be > 0"}},
      {"ResolutionZero", [] { return edited([](json& s) { s["geometry"][0]["box"]["resolution"][2] = 0; }); },
       {"scene.json: geometry[0].box.resolution[2] = 0: must be >= 1"}},
      {"ResolutionNotInteger", [] { return edited([](json& s) { s["geometry"][0]["box"]["resolution"][0] = 2.5; }); },
       {"scene.json: geometry[0].box.resolution[0]: expected an integer, got number 2.5"}},
      {"TranslationOnBox", [] { return edited([](json& s) { s["geometry"][0]["translation"] = {1, 0, 0}; }); },
       {"scene.json: geometry[0].translation: applies to a \"mesh\" body only"}},
      {"ScaleZero", [] { return edited([](json& s) {
         s["geometry"][0].erase("box");
         s["geometry"][0]["mesh"] = "a.msh";
         s["geometry"][0]["scale"] = 0;
       }); },
       {"scene.json: geometry[0].scale = 0: must be > 0"}},
      {"ZeroAxis", [] { return edited([](json& s) { s["boundary_conditions"]["dirichlet"][2]["axis"] = {0, 0, 0}; }); },
       {"scene.json: boundary_conditions.dirichlet[2].axis = [0,0,0]: rotation axis must be non-zero"}},
      {"RotationWithoutSpeed", [] { return edited([](json& s) { s["boundary_conditions"]["dirichlet"][2].erase("angular_velocity"); }); },
       {"scene.json: boundary_conditions.dirichlet[2].angular_velocity: required key is missing"}},
      {"UnknownBcType", [] { return edited([](json& s) { s["boundary_conditions"]["dirichlet"][0]["type"] = "clamped"; }); },
       {"scene.json: boundary_conditions.dirichlet[0].type = \"clamped\": unknown type (allowed: fixed, velocity, rotation)"}},
      {"SelectionBoxInverted", [] { return edited([](json& s) { s["boundary_conditions"]["dirichlet"][1]["selection"]["box"][1][0] = 0.5; }); },
       {"scene.json: boundary_conditions.dirichlet[1].selection.box: min corner exceeds max corner in coordinate 0 (0.9 > 0.5)"}},
      {"SelectionWrongType", [] { return edited([](json& s) { s["boundary_conditions"]["dirichlet"][0]["selection"] = 3; }); },
       {"scene.json: boundary_conditions.dirichlet[0].selection: expected a node set name or {\"box\""}},
      {"MissingTime", [] { return edited([](json& s) { s.erase("time"); }); }, {"scene.json: time: required key is missing"}},
      {"MissingDt", [] { return edited([](json& s) { s["time"].erase("dt"); }); }, {"scene.json: time.dt: required key is missing"}},
      {"MissingSteps", [] { return edited([](json& s) { s["time"].erase("steps"); }); },
       {"scene.json: time: needs \"steps\" or \"t_end\""}},
      {"StepsAndTEnd", [] { return edited([](json& s) { s["time"]["t_end"] = 0.1; }); },
       {"scene.json: time: give either \"steps\" or \"t_end\", not both"}},
      {"StepsZero", [] { return edited([](json& s) { s["time"]["steps"] = 0; }); }, {"scene.json: time.steps = 0: must be >= 1"}},
      {"StepsTooLarge", [] { return edited([](json& s) { s["time"]["steps"] = 99999999999LL; }); },
       {"scene.json: time.steps = 99999999999: too large (at most 2147483647)"}},
      {"TEndNotMultiple", [] { return edited([](json& s) { s["time"].erase("steps"); s["time"]["t_end"] = 0.015; }); },
       {"scene.json: time.t_end = 0.015: not a whole number of steps of dt = 0.01 (1.5 steps)"}},
      {"TEndTooShort", [] { return edited([](json& s) { s["time"].erase("steps"); s["time"]["t_end"] = 0.004; }); },
       {"scene.json: time.t_end = 0.004: shorter than one step of dt = 0.01"}},
      {"UnknownIntegrator", [] { return edited([](json& s) { s["time"]["integrator"] = "newmark"; }); },
       {"scene.json: time.integrator = \"newmark\": unknown integrator (allowed: implicit_euler, static)"}},
      {"StaticWithTEnd",
       [] {
         return edited([](json& s) {
           s["time"] = {{"integrator", "static"}, {"t_end", 1.0}};
         });
       },
       {"scene.json: time.t_end: unknown key (allowed for integrator \"static\": integrator, dt, steps)"}},
      {"UnknownMass", [] { return edited([](json& s) { s["solver"]["mass"] = "diagonal"; }); },
       {"scene.json: solver.mass = \"diagonal\": unknown mass matrix (allowed: lumped, consistent)"}},
      {"EveryZero", [] { return edited([](json& s) { s["output"]["every"] = 0; }); }, {"scene.json: output.every = 0: must be >= 1"}},
      {"OutputNameWithSlash", [] { return edited([](json& s) { s["output"]["name"] = "a/b"; }); },
       {"scene.json: output.name = \"a/b\": must be a non-empty file name without '/'"}},
      {"DhatZero", [] { return edited([](json& s) { s["contact"]["dhat"] = 0; }); }, {"scene.json: contact.dhat = 0: must be > 0"}},
      {"FrictionNegative", [] { return edited([](json& s) { s["contact"]["friction"] = -0.1; }); },
       {"scene.json: contact.friction = -0.1: must be >= 0"}},
      {"EnabledNotBool", [] { return edited([](json& s) { s["contact"]["enabled"] = 1; }); },
       {"scene.json: contact.enabled: expected true or false, got number 1"}},
  };
}

std::string error_of(const BadScene& bad) {
  try {
    parse_scene_text(bad.text(), "scene.json", "/base");
  } catch (const SceneError& e) {
    return e.what();
  }
  return "";
}

class BadSceneTest : public ::testing::TestWithParam<BadScene> {};

TEST_P(BadSceneTest, IsRejectedWithItsMessage) {
  const std::string message = error_of(GetParam());
  ASSERT_FALSE(message.empty()) << "the scene was accepted";
  for (const std::string& part : GetParam().expected) EXPECT_NE(message.find(part), std::string::npos) << message;
}

INSTANTIATE_TEST_SUITE_P(SceneParser, BadSceneTest, ::testing::ValuesIn(bad_scenes()),
                         [](const ::testing::TestParamInfo<BadScene>& info) { return info.param.name; });

TEST(SceneParser, EveryBadSceneHasADistinctMessage) {
  std::set<std::string> messages;
  for (const BadScene& bad : bad_scenes()) {
    EXPECT_TRUE(messages.insert(error_of(bad)).second) << bad.name << ": " << error_of(bad);
  }
}

TEST(SceneParser, MinimalSceneTakesTheDefaults) {
  const Scene scene = parse_scene_text(R"({"materials": [{}], "geometry": [{"box": {}}],
                                           "time": {"dt": 0.1, "steps": 3}})",
                                       "minimal.json", "");
  const Material defaults;
  ASSERT_EQ(scene.materials.size(), 1u);
  EXPECT_EQ(scene.materials[0].E, defaults.E);
  EXPECT_EQ(scene.materials[0].nu, defaults.nu);
  EXPECT_EQ(scene.materials[0].rho, defaults.rho);
  ASSERT_EQ(scene.bodies.size(), 1u);
  EXPECT_EQ(scene.bodies[0].name, "body0");
  ASSERT_TRUE(scene.bodies[0].box.has_value());
  EXPECT_EQ(scene.bodies[0].box->resolution, (std::array<int, 3>{1, 1, 1}));
  EXPECT_EQ(scene.bodies[0].box->size, (std::array<double, 3>{1, 1, 1}));
  EXPECT_EQ(scene.bodies[0].material, 0u);
  EXPECT_EQ(scene.gravity, (std::array<double, 3>{0, 0, 0}));
  EXPECT_TRUE(scene.dirichlet.empty());
  EXPECT_FALSE(scene.is_static);
  EXPECT_EQ(scene.dt, 0.1);
  EXPECT_EQ(scene.steps, 3);
  EXPECT_TRUE(scene.lumped_mass);
  EXPECT_EQ(scene.output_directory, "output");
  EXPECT_EQ(scene.output_name, "dipc");
  EXPECT_EQ(scene.output_every, 1);
  EXPECT_FALSE(scene.contact.enabled);
  EXPECT_EQ(scene.contact.dhat, 1e-3);
  EXPECT_TRUE(scene.contact.dhat_relative);
  EXPECT_EQ(scene.contact.friction, 0.0);
  EXPECT_EQ(scene.source, "minimal.json");
}

TEST(SceneParser, FullSceneFileParsesToItsValues) {
  const std::string path = std::string(DIPC_IO_TEST_DATA) + "/two_bodies.json";
  const Scene scene = parse_scene_file(path);
  EXPECT_EQ(scene.source, path);
  ASSERT_EQ(scene.materials.size(), 2u);
  EXPECT_EQ(scene.materials[1].name, "steel");
  EXPECT_EQ(scene.materials[1].E, 2e11);
  EXPECT_EQ(scene.materials[1].rho, 7850);

  ASSERT_EQ(scene.bodies.size(), 2u);
  const Body& beam = scene.bodies[0];
  EXPECT_EQ(beam.material, 0u);  // by name
  EXPECT_EQ(beam.box->resolution, (std::array<int, 3>{20, 2, 2}));
  EXPECT_EQ(beam.initial_velocity, (std::array<double, 3>{0, 0, -1}));
  const Body& part = scene.bodies[1];
  EXPECT_EQ(part.material, 1u);  // by index
  EXPECT_FALSE(part.box.has_value());
  const auto expected_mesh =
      (std::filesystem::absolute(DIPC_IO_TEST_DATA) / "meshes" / "part.msh").lexically_normal();
  EXPECT_EQ(part.mesh_file, expected_mesh.string());
  EXPECT_EQ(part.translation, (std::array<double, 3>{0, 0, 1}));
  EXPECT_EQ(part.scale, 2.0);

  EXPECT_EQ(scene.gravity, (std::array<double, 3>{0, 0, -9.81}));
  ASSERT_EQ(scene.dirichlet.size(), 3u);
  EXPECT_EQ(scene.dirichlet[0].kind, DirichletCondition::Kind::Fixed);
  EXPECT_EQ(scene.dirichlet[0].selection.name, "beam.xmin");
  EXPECT_EQ(scene.dirichlet[0].key_path, "boundary_conditions.dirichlet[0]");
  EXPECT_EQ(scene.dirichlet[1].kind, DirichletCondition::Kind::Velocity);
  ASSERT_TRUE(scene.dirichlet[1].selection.box.has_value());
  EXPECT_EQ(*scene.dirichlet[1].selection.box, (std::array<double, 6>{-1, -1, -1, 0.001, 1, 1}));
  EXPECT_EQ(scene.dirichlet[1].velocity, (std::array<double, 3>{0, 0, 0.1}));
  const DirichletCondition& rotation = scene.dirichlet[2];
  EXPECT_EQ(rotation.kind, DirichletCondition::Kind::Rotation);
  EXPECT_EQ(rotation.axis, (std::array<double, 3>{0, 0, 1}));  // normalised from [0, 0, 2]
  EXPECT_EQ(rotation.center, (std::array<double, 3>{0.5, 0, 1}));
  EXPECT_EQ(rotation.angular_velocity, 3.14);

  EXPECT_EQ(scene.dt, 0.01);
  EXPECT_EQ(scene.steps, 100);  // t_end = 1.0
  EXPECT_FALSE(scene.lumped_mass);
  EXPECT_EQ(scene.output_directory, "results");
  EXPECT_EQ(scene.output_name, "two_bodies");
  EXPECT_EQ(scene.output_every, 5);
  EXPECT_TRUE(scene.contact.enabled);
  EXPECT_FALSE(scene.contact.dhat_relative);
  EXPECT_EQ(scene.contact.friction, 0.2);
  EXPECT_EQ(scene.contact.epsv, 1e-4);
}

TEST(SceneParser, TEndGivesTheNearestWholeStepCount) {
  json scene = base_scene();
  scene["time"] = {{"dt", 0.1}, {"t_end", 0.7}};  // 0.7 / 0.1 = 6.999999999999999
  EXPECT_EQ(parse(scene).steps, 7);
  scene["time"] = {{"dt", 1e-3}, {"t_end", 2.5}};
  EXPECT_EQ(parse(scene).steps, 2500);
}

TEST(SceneParser, MeshPathsAreResolvedAgainstTheSceneDirectory) {
  json scene = base_scene();
  scene["geometry"][0].erase("box");
  scene["geometry"][0]["mesh"] = "../meshes/./part.msh";
  EXPECT_EQ(parse_scene_text(scene.dump(), "s.json", "/data/scenes").bodies[0].mesh_file, "/data/meshes/part.msh");
  scene["geometry"][0]["mesh"] = "/abs/part.msh";
  EXPECT_EQ(parse_scene_text(scene.dump(), "s.json", "/data/scenes").bodies[0].mesh_file, "/abs/part.msh");
  scene["geometry"][0]["mesh"] = "part.msh";
  EXPECT_EQ(parse_scene_text(scene.dump(), "s.json", "").bodies[0].mesh_file,
            (std::filesystem::current_path() / "part.msh").string());
}

TEST(SceneParser, StaticIntegratorDefaultsToOneLoadStep) {
  json scene = base_scene();
  scene["time"] = {{"integrator", "static"}};
  const Scene parsed = parse(scene);
  EXPECT_TRUE(parsed.is_static);
  EXPECT_EQ(parsed.steps, 1);
  EXPECT_EQ(parsed.dt, 1.0);
}

TEST(SceneParser, StaticLoadSteps) {
  json scene = base_scene();
  scene["time"] = {{"integrator", "static"}, {"dt", 0.25}, {"steps", 4}};
  const Scene parsed = parse(scene);
  EXPECT_TRUE(parsed.is_static);
  EXPECT_EQ(parsed.steps, 4);
  EXPECT_EQ(parsed.dt, 0.25);
}

TEST(SceneParser, MissingFileIsNamed) {
  try {
    parse_scene_file("/nonexistent/dir/scene.json");
    FAIL() << "no exception";
  } catch (const SceneError& e) {
    EXPECT_EQ(std::string(e.what()), "/nonexistent/dir/scene.json: cannot open scene file");
  }
}

TEST(SceneParser, SelectionDescribesItself) {
  Selection named;
  named.name = "beam.xmin";
  EXPECT_EQ(named.describe(), "node set \"beam.xmin\"");
  Selection box;
  box.box = std::array<double, 6>{0, -1, -1, 0.001, 1, 1};
  EXPECT_EQ(box.describe(), "box [0, -1, -1] - [0.001, 1, 1]");
}

TEST(DefaultScene, IsTheDocumentedCantilever) {
  const Scene scene = default_scene();
  EXPECT_EQ(scene.source, "<default scene>");
  ASSERT_EQ(scene.materials.size(), 1u);
  EXPECT_EQ(scene.materials[0].E, 1e6);
  EXPECT_EQ(scene.materials[0].nu, 0.4);
  EXPECT_EQ(scene.materials[0].rho, 1000);
  ASSERT_EQ(scene.bodies.size(), 1u);
  EXPECT_EQ(scene.bodies[0].name, "beam");
  ASSERT_TRUE(scene.bodies[0].box.has_value());
  EXPECT_EQ(scene.bodies[0].box->size, (std::array<double, 3>{1.0, 0.1, 0.1}));
  EXPECT_EQ(scene.bodies[0].box->resolution, (std::array<int, 3>{24, 3, 3}));
  ASSERT_EQ(scene.dirichlet.size(), 1u);
  EXPECT_EQ(scene.dirichlet[0].selection.name, "beam.xmin");
  EXPECT_EQ(scene.dirichlet[0].kind, DirichletCondition::Kind::Fixed);
  EXPECT_EQ(scene.gravity, (std::array<double, 3>{0, 0, -9.81}));
  EXPECT_EQ(scene.dt, 0.01);
  EXPECT_EQ(scene.steps, 50);
  EXPECT_EQ(scene.output_directory, "output");
  EXPECT_EQ(scene.output_name, "dipc");
}

// The example file shipped for users must stay the scene the program embeds.
TEST(DefaultScene, MatchesTheExampleFile) {
  std::ifstream in(std::string(DIPC_IO_TEST_DATA) + "/default_scene.json");
  ASSERT_TRUE(in) << "missing tests/io/data/default_scene.json";
  std::ostringstream text;
  text << in.rdbuf();
  EXPECT_EQ(json::parse(text.str()), json::parse(default_scene_json()));
}

}  // namespace
}  // namespace dipc
