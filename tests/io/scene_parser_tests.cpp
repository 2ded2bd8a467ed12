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
  std::function<std::string()> text;  // the scene file's text
  std::vector<std::string> expected;  // substrings of the error message
};

// gtest prints a failing parameter with this instead of its bytes.
void PrintTo(const BadScene& bad, std::ostream* os) { *os << bad.name; }

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
      {"BadJson",
       [] { return std::string("{\n  \"materials\": [,]\n}"); },
       {"scene.json: invalid JSON: parse error at line 2, column 17"}},
      {"NotAnObject", [] { return std::string("[1, 2]"); }, {"scene.json: expected an object, got array"}},
      {"UnknownTopLevelKey",
       [] { return edited([](json& s) { s["meterials"] = json::array(); }); },
       {"scene.json: meterials: unknown key (allowed: materials, geometry, boundary_conditions, time"}},
      {"UnknownNestedKey",
       [] { return edited([](json& s) { s["geometry"][0]["box"]["sise"] = 1; }); },
       {"scene.json: geometry[0].box.sise: unknown key (allowed: size, resolution, origin)"}},
      {"KeyOfAnotherBcType",
       [] { return edited([](json& s) {
              s["boundary_conditions"]["dirichlet"][0]["velocity"] = {0, 0, 1};
            }); },
       {"boundary_conditions.dirichlet[0].velocity: unknown key (allowed for type \"fixed\": selection, type)"}},
      {"DuplicateKey",
       [] { return raw("\"E\": 1000000.0", "\"E\": 1000000.0, \"E\": 2"); },
       {"scene.json: materials[0].E: duplicate key"}},
      {"WrongType",
       [] { return edited([](json& s) { s["time"]["dt"] = "0.01"; }); },
       {"scene.json: time.dt: expected a number, got string \"0.01\""}},
      {"WrongTypeDeep",
       [] { return edited([](json& s) { s["boundary_conditions"]["dirichlet"][1]["velocity"][2] = "up"; }); },
       {"scene.json: boundary_conditions.dirichlet[1].velocity[2]: expected a number, got string"}},
      {"WrongLength",
       [] { return edited([](json& s) {
              s["boundary_conditions"]["gravity"] = {0, -9.81};
            }); },
       {"scene.json: boundary_conditions.gravity: expected an array of 3 numbers, got 2"}},
      {"NuHalf",
       [] { return edited([](json& s) { s["materials"][0]["nu"] = 0.5; }); },
       {"scene.json: materials[0].nu = 0.5: must be in (-1, 0.5)"}},
      {"NuMinusOne",
       [] { return edited([](json& s) { s["materials"][0]["nu"] = -1; }); },
       {"scene.json: materials[0].nu = -1: must be in (-1, 0.5)"}},
      {"EZero",
       [] { return edited([](json& s) { s["materials"][0]["E"] = 0; }); },
       {"scene.json: materials[0].E = 0: must be > 0"}},
      {"RhoNegative",
       [] { return edited([](json& s) { s["materials"][0]["rho"] = -5; }); },
       {"scene.json: materials[0].rho = -5: must be > 0"}},
      {"UnknownModel",
       [] { return edited([](json& s) { s["materials"][0]["model"] = "mooney_rivlin"; }); },
       {"scene.json: materials[0].model = \"mooney_rivlin\": must be \"neo_hookean\" or \"stable_neo_hookean\""}},
      {"StableNeoHookeanMeanDilatation",
       [] {
         return edited([](json& s) {
           s["materials"][0]["model"] = "stable_neo_hookean";
           s["materials"][0]["volumetric"] = "mean_dilatation";
         });
       },
       {"scene.json: materials[0].model = \"stable_neo_hookean\": has no mean-dilatation element"}},
      {"DtZero", [] { return edited([](json& s) { s["time"]["dt"] = 0; }); }, {"scene.json: time.dt = 0: must be > 0"}},
      {"Overflow",
       [] { return raw("-9.81", "1e999"); },
       {"scene.json: boundary_conditions.gravity[2]: number overflow parsing '1e999'", "must be finite"}},
      {"EmptyMaterials",
       [] { return edited([](json& s) { s["materials"] = json::array(); }); },
       {"scene.json: materials: must list at least one material"}},
      {"DuplicateMaterial",
       [] { return edited([](json& s) {
              s["materials"].push_back({{"name", "rubber"}});
            }); },
       {"scene.json: materials[1].name = \"rubber\": duplicate material name (also materials[0].name)"}},
      {"UnknownMaterial",
       [] { return edited([](json& s) { s["geometry"][0]["material"] = "steel"; }); },
       {"scene.json: geometry[0].material = \"steel\": unknown material (known: rubber)"}},
      {"MaterialIndexOutOfRange",
       [] { return edited([](json& s) { s["geometry"][0]["material"] = 1; }); },
       {"scene.json: geometry[0].material = 1: material index must be in [0, 1)"}},
      {"MaterialMissingWithTwo",
       [] {
         return edited([](json& s) {
           s["materials"].push_back({{"name", "steel"}});
           s["geometry"][0].erase("material");
         });
       },
       {"scene.json: geometry[0]: \"material\" is required when the scene has 2 materials"}},
      {"BoxAndMesh",
       [] { return edited([](json& s) { s["geometry"][0]["mesh"] = "a.msh"; }); },
       {"scene.json: geometry[0]: give either \"box\" or \"mesh\", not both"}},
      {"NeitherBoxNorMesh",
       [] { return edited([](json& s) { s["geometry"][0].erase("box"); }); },
       {"scene.json: geometry[0]: needs a \"box\" or a \"mesh\""}},
      {"DuplicateBody",
       [] { return edited([](json& s) { s["geometry"].push_back(s["geometry"][0]); }); },
       {"scene.json: geometry[1]: duplicate body name \"beam\" (also geometry[0])"}},
      {"BodyNameWithDot",
       [] { return edited([](json& s) { s["geometry"][0]["name"] = "a.b"; }); },
       {"scene.json: geometry[0].name = \"a.b\": must not contain '.'"}},
      {"BoxSizeZero",
       [] { return edited([](json& s) { s["geometry"][0]["box"]["size"][1] = 0; }); },
       {"scene.json: geometry[0].box.size[1] = 0: must be > 0"}},
      {"ResolutionZero",
       [] { return edited([](json& s) { s["geometry"][0]["box"]["resolution"][2] = 0; }); },
       {"scene.json: geometry[0].box.resolution[2] = 0: must be >= 1"}},
      {"ResolutionNotInteger",
       [] { return edited([](json& s) { s["geometry"][0]["box"]["resolution"][0] = 2.5; }); },
       {"scene.json: geometry[0].box.resolution[0]: expected an integer, got number 2.5"}},
      {"TranslationOnBox",
       [] { return edited([](json& s) {
              s["geometry"][0]["translation"] = {1, 0, 0};
            }); },
       {"scene.json: geometry[0].translation: applies to a \"mesh\" body only"}},
      {"ScaleZero",
       [] {
         return edited([](json& s) {
           s["geometry"][0].erase("box");
           s["geometry"][0]["mesh"] = "a.msh";
           s["geometry"][0]["scale"] = 0;
         });
       },
       {"scene.json: geometry[0].scale = 0: must be > 0"}},
      {"ZeroAxis",
       [] { return edited([](json& s) {
              s["boundary_conditions"]["dirichlet"][2]["axis"] = {0, 0, 0};
            }); },
       {"scene.json: boundary_conditions.dirichlet[2].axis = [0,0,0]: rotation axis must be non-zero"}},
      {"RotationWithoutSpeed",
       [] { return edited([](json& s) { s["boundary_conditions"]["dirichlet"][2].erase("angular_velocity"); }); },
       {"scene.json: boundary_conditions.dirichlet[2].angular_velocity: required key is missing"}},
      {"UnknownBcType",
       [] { return edited([](json& s) { s["boundary_conditions"]["dirichlet"][0]["type"] = "clamped"; }); },
       {"scene.json: boundary_conditions.dirichlet[0].type = \"clamped\": unknown type (allowed: fixed, velocity, "
        "rotation, path)"}},
      {"SelectionBoxInverted",
       [] { return edited([](json& s) { s["boundary_conditions"]["dirichlet"][1]["selection"]["box"][1][0] = 0.5; }); },
       {"scene.json: boundary_conditions.dirichlet[1].selection.box: min corner exceeds max corner in coordinate 0 "
        "(0.9 > 0.5)"}},
      {"SelectionWrongType",
       [] { return edited([](json& s) { s["boundary_conditions"]["dirichlet"][0]["selection"] = 3; }); },
       {"scene.json: boundary_conditions.dirichlet[0].selection: expected a node set name or {\"box\""}},
      {"MissingTime",
       [] { return edited([](json& s) { s.erase("time"); }); },
       {"scene.json: time: required key is missing"}},
      {"MissingDt",
       [] { return edited([](json& s) { s["time"].erase("dt"); }); },
       {"scene.json: time.dt: required key is missing"}},
      {"MissingSteps",
       [] { return edited([](json& s) { s["time"].erase("steps"); }); },
       {"scene.json: time: needs \"steps\" or \"t_end\""}},
      {"StepsAndTEnd",
       [] { return edited([](json& s) { s["time"]["t_end"] = 0.1; }); },
       {"scene.json: time: give either \"steps\" or \"t_end\", not both"}},
      {"StepsZero",
       [] { return edited([](json& s) { s["time"]["steps"] = 0; }); },
       {"scene.json: time.steps = 0: must be >= 1"}},
      {"StepsTooLarge",
       [] { return edited([](json& s) { s["time"]["steps"] = 99999999999LL; }); },
       {"scene.json: time.steps = 99999999999: too large (at most 2147483647)"}},
      {"TEndNotMultiple",
       [] {
         return edited([](json& s) {
           s["time"].erase("steps");
           s["time"]["t_end"] = 0.015;
         });
       },
       {"scene.json: time.t_end = 0.015: not a whole number of steps of dt = 0.01 (1.5 steps)"}},
      {"TEndTooShort",
       [] {
         return edited([](json& s) {
           s["time"].erase("steps");
           s["time"]["t_end"] = 0.004;
         });
       },
       {"scene.json: time.t_end = 0.004: shorter than one step of dt = 0.01"}},
      {"UnknownIntegrator",
       [] { return edited([](json& s) { s["time"]["integrator"] = "newmark"; }); },
       {"scene.json: time.integrator = \"newmark\": unknown integrator (allowed: implicit_euler, static)"}},
      {"StaticWithTEnd",
       [] { return edited([](json& s) {
              s["time"] = {{"integrator", "static"}, {"t_end", 1.0}};
            }); },
       {"scene.json: time.t_end: unknown key (allowed for integrator \"static\": integrator, dt, steps)"}},
      {"UnknownMass",
       [] { return edited([](json& s) { s["solver"]["mass"] = "diagonal"; }); },
       {"scene.json: solver.mass = \"diagonal\": unknown mass matrix (allowed: lumped, consistent)"}},
      {"EveryZero",
       [] { return edited([](json& s) { s["output"]["every"] = 0; }); },
       {"scene.json: output.every = 0: must be >= 1"}},
      {"OutputNameWithSlash",
       [] { return edited([](json& s) { s["output"]["name"] = "a/b"; }); },
       {"scene.json: output.name = \"a/b\": must be a non-empty file name without '/'"}},
      {"DhatZero",
       [] { return edited([](json& s) { s["contact"]["dhat"] = 0; }); },
       {"scene.json: contact.dhat = 0: must be > 0"}},
      {"FrictionNegative",
       [] { return edited([](json& s) { s["contact"]["friction"] = -0.1; }); },
       {"scene.json: contact.friction = -0.1: must be >= 0"}},
      {"EnabledNotBool",
       [] { return edited([](json& s) { s["contact"]["enabled"] = 1; }); },
       {"scene.json: contact.enabled: expected true or false, got number 1"}},
      {"ContactUnknownKey",
       [] { return edited([](json& s) { s["contact"]["mu"] = 0.3; }); },
       {"scene.json: contact.mu: unknown key (allowed: enabled, dhat, dhat_relative, barrier_stiffness, "
        "friction, epsv, friction_iterations, planes, obstacles)"}},
      {"DhatNegative",
       [] { return edited([](json& s) { s["contact"]["dhat"] = -1e-3; }); },
       {"scene.json: contact.dhat = -0.001: must be > 0"}},
      {"DhatRelativeWholeDiagonal",
       [] { return edited([](json& s) { s["contact"]["dhat"] = 1; }); },
       {"scene.json: contact.dhat = 1: a relative dhat is a fraction of the bounding-box diagonal, must be < 1"}},
      {"BarrierStiffnessAuto",
       [] { return edited([](json& s) { s["contact"]["barrier_stiffness"] = "auto"; }); },
       {"scene.json: contact.barrier_stiffness = \"auto\": unknown barrier stiffness (allowed: \"adaptive\" or a "
        "number > 0)"}},
      {"BarrierStiffnessZero",
       [] { return edited([](json& s) { s["contact"]["barrier_stiffness"] = 0; }); },
       {"scene.json: contact.barrier_stiffness = 0: must be > 0"}},
      {"BarrierStiffnessNegative",
       [] { return edited([](json& s) { s["contact"]["barrier_stiffness"] = -1e4; }); },
       {"scene.json: contact.barrier_stiffness = -10000.0: must be > 0"}},
      {"BarrierStiffnessBool",
       [] { return edited([](json& s) { s["contact"]["barrier_stiffness"] = true; }); },
       {"scene.json: contact.barrier_stiffness: expected \"adaptive\" or a number > 0"}},
      {"EpsvZero",
       [] { return edited([](json& s) { s["contact"]["epsv"] = 0; }); },
       {"scene.json: contact.epsv = 0: must be > 0"}},
      {"EpsvNegative",
       [] { return edited([](json& s) { s["contact"]["epsv"] = -1e-3; }); },
       {"scene.json: contact.epsv = -0.001: must be > 0"}},
      {"FrictionIterationsZero",
       [] { return edited([](json& s) { s["contact"]["friction_iterations"] = 0; }); },
       {"scene.json: contact.friction_iterations = 0: must be >= 1"}},
      {"FrictionIterationsNotInteger",
       [] { return edited([](json& s) { s["contact"]["friction_iterations"] = 1.5; }); },
       {"scene.json: contact.friction_iterations: expected an integer, got number 1.5"}},
      {"PlanesNotArray",
       [] { return edited([](json& s) {
              s["contact"]["planes"] = {{"normal", {0, 0, 1}}};
            }); },
       {"scene.json: contact.planes: expected an array, got object"}},
      {"PlaneZeroNormal",
       [] {
         return edited([](json& s) {
           s["contact"]["planes"] = json::array({{{"point", {0, 0, 0}}, {"normal", {0, 0, 0}}}});
         });
       },
       {"scene.json: contact.planes[0].normal = [0,0,0]: plane normal must be non-zero"}},
      {"PlaneWithoutNormal",
       [] {
         return edited([](json& s) {
           s["contact"]["planes"] = json::array(
               {{{"point", {0, 0, 0}}, {"normal", {0, 0, 1}}}, {{"point", {0, 0, 1}}}});
         });
       },
       {"scene.json: contact.planes[1].normal: required key is missing"}},
      {"PlaneUnknownKey",
       [] {
         return edited([](json& s) {
           s["contact"]["planes"] = json::array({{{"origin", {0, 0, 0}}, {"normal", {0, 0, 1}}}});
         });
       },
       {"scene.json: contact.planes[0].origin: unknown key (allowed: point, normal)"}},
      {"SelfContactNotBool",
       [] { return edited([](json& s) { s["geometry"][0]["self_contact"] = "yes"; }); },
       {"scene.json: geometry[0].self_contact: expected true or false, got string \"yes\""}},
      {"KinematicUnknownType",
       [] {
         return edited([](json& s) {
           s["boundary_conditions"].erase("dirichlet");
           s["geometry"][0]["kinematic"] = {{"type", "spin"}};
         });
       },
       {"scene.json: geometry[0].kinematic.type = \"spin\": unknown type (allowed: fixed, velocity, rotation, path)"}},
      {"KinematicNotObject",
       [] {
         return edited([](json& s) {
           s["boundary_conditions"].erase("dirichlet");
           s["geometry"][0]["kinematic"] = true;
         });
       },
       {"scene.json: geometry[0].kinematic: expected an object, got boolean true"}},
      {"KinematicVelocityMissing",
       [] {
         return edited([](json& s) {
           s["boundary_conditions"].erase("dirichlet");
           s["geometry"][0]["kinematic"] = {{"type", "velocity"}};
         });
       },
       {"scene.json: geometry[0].kinematic.velocity: required key is missing"}},
      {"KinematicWithSelection",
       [] {
         return edited([](json& s) {
           s["boundary_conditions"].erase("dirichlet");
           s["geometry"][0]["kinematic"] = {{"selection", "beam.xmin"}};
         });
       },
       {"scene.json: geometry[0].kinematic.selection: unknown key (allowed for type \"fixed\": type)"}},
      {"KinematicZeroAxis",
       [] {
         return edited([](json& s) {
           s["boundary_conditions"].erase("dirichlet");
           s["geometry"][0]["kinematic"] = {{"type", "rotation"}, {"axis", {0, 0, 0}}, {"angular_velocity", 1}};
         });
       },
       {"scene.json: geometry[0].kinematic.axis = [0,0,0]: rotation axis must be non-zero"}},
      {"KinematicWithInitialVelocity",
       [] {
         return edited([](json& s) {
           s["boundary_conditions"].erase("dirichlet");
           s["geometry"][0]["kinematic"] = json::object();
           s["geometry"][0]["initial_velocity"] = {1, 0, 0};
         });
       },
       {"scene.json: geometry[0].initial_velocity: a kinematic body's motion is prescribed by \"kinematic\", "
        "not by an initial velocity"}},
      {"DirichletOnKinematicBody",
       [] { return edited([](json& s) { s["geometry"][0]["kinematic"] = json::object(); }); },
       {"scene.json: boundary_conditions.dirichlet[0].selection = \"beam.xmin\": body \"beam\" is kinematic "
        "(geometry[0].kinematic prescribes all its nodes)"}},
      {"DirichletOnWholeKinematicBody",
       [] {
         return edited([](json& s) {
           s["geometry"][0]["kinematic"] = json::object();
           s["boundary_conditions"]["dirichlet"] = json::array({{{"selection", "beam"}}});
         });
       },
       {"scene.json: boundary_conditions.dirichlet[0].selection = \"beam\": body \"beam\" is kinematic"}},
      {"ObstacleWithoutContact",
       [] { return edited([](json& s) {
              s["contact"] = {{"obstacles", json::array({{{"mesh", "floor.obj"}}})}};
            }); },
       {"scene.json: contact.obstacles: triangle-mesh obstacles need contact (\"enabled\": true)"}},
      {"ObstacleUnknownKey",
       [] {
         return edited([](json& s) {
           s["contact"] = {{"enabled", true}, {"obstacles", json::array({{{"mesh", "floor.obj"}, {"rotation", 1}}})}};
         });
       },
       {"scene.json: contact.obstacles[0].rotation: unknown key (allowed: name, mesh, scale, translation, motion)"}},
      {"ObstacleWithoutMesh",
       [] {
         return edited([](json& s) {
           s["contact"] = {{"enabled", true}, {"obstacles", json::array({{{"name", "floor"}}})}};
         });
       },
       {"scene.json: contact.obstacles[0].mesh: required key is missing"}},
      {"ObstacleZeroScale",
       [] {
         return edited([](json& s) {
           s["contact"] = {{"enabled", true}, {"obstacles", json::array({{{"mesh", "f.obj"}, {"scale", 0}}})}};
         });
       },
       {"scene.json: contact.obstacles[0].scale = 0: must be > 0"}},
      {"ObstacleDuplicateName",
       [] {
         return edited([](json& s) {
           s["contact"] = {{"enabled", true},
                           {"obstacles",
                            json::array({{{"mesh", "a.obj"}, {"name", "f"}}, {{"mesh", "b.obj"}, {"name", "f"}}})}};
         });
       },
       {"scene.json: contact.obstacles[1]: duplicate obstacle name \"f\" (also contact.obstacles[0])"}},
      {"PathTooShort",
       [] {
         return edited([](json& s) {
           s["boundary_conditions"]["dirichlet"][0] = {{"selection", "beam.xmin"},
                                                       {"type", "path"},
                                                       {"keyframes",
                                                        json::array({{{"time", 0}, {"translation", {0, 0, 0}}}})}};
         });
       },
       {"scene.json: boundary_conditions.dirichlet[0].keyframes: a path needs at least two keyframes, got 1"}},
      {"PathStartsLate",
       [] {
         return edited([](json& s) {
           s["boundary_conditions"]["dirichlet"][0] = {{"selection", "beam.xmin"},
                                                       {"type", "path"},
                                                       {"keyframes",
                                                        json::array({{{"time", 0.5}, {"translation", {0, 0, 0}}},
                                                                     {{"time", 1}, {"translation", {0, 0, 1}}}})}};
         });
       },
       {"scene.json: boundary_conditions.dirichlet[0].keyframes[0].time = 0.5: the first keyframe must be at time 0"}},
      {"PathStartsAway",
       [] {
         return edited([](json& s) {
           s["contact"] = {{"enabled", true},
                           {"obstacles",
                            json::array(
                                {{{"mesh", "f.obj"},
                                  {"motion",
                                   {{"type", "path"},
                                    {"keyframes", json::array({{{"time", 0}, {"translation", {0, 0, 1}}},
                                                               {{"time", 1}, {"translation", {0, 0, 2}}}})}}}}})}};
         });
       },
       {"scene.json: contact.obstacles[0].motion.keyframes[0].translation = [0,0,1]: the first keyframe's translation "
        "must be [0, 0, 0]"}},
      {"PathTimesDoNotIncrease",
       [] {
         return edited([](json& s) {
           s["geometry"][0]["kinematic"] = {{"type", "path"},
                                            {"keyframes", json::array({{{"time", 0}, {"translation", {0, 0, 0}}},
                                                                       {{"time", 1}, {"translation", {0, 0, 1}}},
                                                                       {{"time", 1}, {"translation", {0, 0, 2}}}})}};
           s["boundary_conditions"].erase("dirichlet");
         });
       },
       {"scene.json: geometry[0].kinematic.keyframes[2].time = 1: keyframe times must strictly increase (previous 1)"}},
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
  EXPECT_EQ(scene.materials[0].model, Material::Model::neo_hookean);
  EXPECT_FALSE(scene.materials[0].mean_dilatation);
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
  EXPECT_EQ(scene.contact.epsv, 1e-3);
  EXPECT_TRUE(scene.contact.kappa_adaptive);
  EXPECT_EQ(scene.contact.kappa, 0.0);
  EXPECT_EQ(scene.contact.friction_iterations, 1);
  EXPECT_TRUE(scene.contact.planes.empty());
  EXPECT_TRUE(scene.bodies[0].self_contact);
  EXPECT_FALSE(scene.bodies[0].kinematic);
  EXPECT_EQ(scene.source, "minimal.json");
}

TEST(SceneParser, MaterialModelIsReadPerMaterial) {
  const Scene scene = parse_scene_text(R"({"materials": [{"name": "a", "model": "stable_neo_hookean"},
                                                         {"name": "b", "model": "neo_hookean",
                                                          "volumetric": "mean_dilatation"}],
                                           "geometry": [{"box": {}, "material": "a"}],
                                           "time": {"dt": 0.1, "steps": 3}})",
                                       "models.json", "");
  ASSERT_EQ(scene.materials.size(), 2u);
  EXPECT_EQ(scene.materials[0].model, Material::Model::stable_neo_hookean);
  EXPECT_FALSE(scene.materials[0].mean_dilatation);
  EXPECT_EQ(scene.materials[1].model, Material::Model::neo_hookean);
  EXPECT_TRUE(scene.materials[1].mean_dilatation);
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
  const auto expected_mesh = (std::filesystem::absolute(DIPC_IO_TEST_DATA) / "meshes" / "part.msh").lexically_normal();
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

TEST(SceneParser, ContactSceneFileParsesToItsValues) {
  const Scene scene = parse_scene_file(std::string(DIPC_IO_TEST_DATA) + "/contact_scene.json");
  const ContactSettings& c = scene.contact;
  EXPECT_TRUE(c.enabled);
  EXPECT_EQ(c.dhat, 2e-4);
  EXPECT_FALSE(c.dhat_relative);
  EXPECT_FALSE(c.kappa_adaptive);
  EXPECT_EQ(c.kappa, 1e7);
  EXPECT_EQ(c.friction, 0.5);
  EXPECT_EQ(c.epsv, 1e-4);
  EXPECT_EQ(c.friction_iterations, 3);
  ASSERT_EQ(c.planes.size(), 2u);
  EXPECT_EQ(c.planes[0].point, (std::array<double, 3>{0, 0, -0.2}));
  EXPECT_EQ(c.planes[0].normal, (std::array<double, 3>{0, 0, 1}));  // normalised from [0, 0, 2]
  EXPECT_EQ(c.planes[1].point, (std::array<double, 3>{1, 0, 0}));
  EXPECT_DOUBLE_EQ(c.planes[1].normal[0], -0.6);  // [-3, 0, 4] / 5
  EXPECT_EQ(c.planes[1].normal[1], 0.0);
  EXPECT_DOUBLE_EQ(c.planes[1].normal[2], 0.8);

  ASSERT_EQ(scene.bodies.size(), 5u);
  const Body& block = scene.bodies[0];
  EXPECT_FALSE(block.self_contact);
  EXPECT_FALSE(block.kinematic);
  EXPECT_EQ(block.initial_velocity, (std::array<double, 3>{1, 0, 0}));
  for (std::size_t i = 1; i < 5; ++i) {
    EXPECT_TRUE(scene.bodies[i].kinematic) << scene.bodies[i].name;
    EXPECT_TRUE(scene.bodies[i].self_contact) << scene.bodies[i].name;
    EXPECT_EQ(scene.bodies[i].initial_velocity, (std::array<double, 3>{0, 0, 0}));
  }

  // The scene's own condition first, then one per kinematic body, in geometry order.
  ASSERT_EQ(scene.dirichlet.size(), 5u);
  EXPECT_EQ(scene.dirichlet[0].key_path, "boundary_conditions.dirichlet[0]");
  EXPECT_TRUE(scene.dirichlet[0].selection.box.has_value());
  const char* names[] = {"upper", "lower", "press", "stop"};
  for (std::size_t k = 0; k < 4; ++k) {
    const DirichletCondition& motion = scene.dirichlet[k + 1];
    EXPECT_EQ(motion.key_path, "geometry[" + std::to_string(k + 1) + "].kinematic");
    EXPECT_EQ(motion.selection.name, names[k]);  // the node set of all the body's nodes
    EXPECT_FALSE(motion.selection.box.has_value());
  }
  const DirichletCondition& upper = scene.dirichlet[1];
  EXPECT_EQ(upper.kind, DirichletCondition::Kind::Rotation);
  EXPECT_EQ(upper.axis, (std::array<double, 3>{0, 1, 0}));  // normalised from [0, 2, 0]
  EXPECT_EQ(upper.center, (std::array<double, 3>{0, 0, 0.16}));
  EXPECT_EQ(upper.angular_velocity, -6.0);
  const DirichletCondition& lower = scene.dirichlet[2];
  EXPECT_EQ(lower.kind, DirichletCondition::Kind::Rotation);
  EXPECT_EQ(lower.center, (std::array<double, 3>{0, 0, -0.06}));
  EXPECT_EQ(lower.angular_velocity, 6.0);
  const DirichletCondition& press = scene.dirichlet[3];
  EXPECT_EQ(press.kind, DirichletCondition::Kind::Velocity);
  EXPECT_EQ(press.velocity, (std::array<double, 3>{0, 0, -0.5}));
  EXPECT_EQ(scene.dirichlet[4].kind, DirichletCondition::Kind::Fixed);  // "kinematic": {}
}

TEST(SceneParser, BarrierStiffnessAdaptiveIsExplicitToo) {
  json scene = base_scene();
  scene["contact"] = {{"barrier_stiffness", 5.0}};
  EXPECT_FALSE(parse(scene).contact.kappa_adaptive);
  EXPECT_EQ(parse(scene).contact.kappa, 5.0);
  scene["contact"] = {{"barrier_stiffness", "adaptive"}};
  EXPECT_TRUE(parse(scene).contact.kappa_adaptive);
  EXPECT_EQ(parse(scene).contact.kappa, 0.0);
}

TEST(SceneParser, AbsoluteDhatMayExceedOne) {
  // Only a relative dhat is bounded by the diagonal; an absolute one is a length.
  json scene = base_scene();
  scene["contact"] = {{"dhat", 2.5}, {"dhat_relative", false}};
  EXPECT_EQ(parse(scene).contact.dhat, 2.5);
  scene["contact"] = {{"dhat", 0.5}};
  EXPECT_EQ(parse(scene).contact.dhat, 0.5);
  EXPECT_TRUE(parse(scene).contact.dhat_relative);
}

TEST(SceneParser, BoxSelectionMayTouchAKinematicBody) {
  // Only named sets of a kinematic body are rejected; a box selection depends on the mesh,
  // and a body whose name merely starts like the kinematic one's is another body.
  json scene = base_scene();
  scene["geometry"].push_back({{"name", "beam2"}, {"box", {{"origin", {0, 0, 1}}}}, {"kinematic", json::object()}});
  scene["boundary_conditions"]["dirichlet"][0]["selection"] = "beam.xmin";
  const Scene parsed = parse(scene);
  ASSERT_EQ(parsed.dirichlet.size(), 4u);
  EXPECT_EQ(parsed.dirichlet[3].selection.name, "beam2");
  EXPECT_EQ(parsed.dirichlet[3].key_path, "geometry[1].kinematic");
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

// An obstacle's keys: mesh resolved against the scene directory, placement and a path motion.
TEST(SceneParser, ObstacleTakesItsValues) {
  json scene = base_scene();
  scene["contact"] = json::parse(R"({"enabled": true, "obstacles": [
      {"mesh": "meshes/floor.obj"},
      {"name": "lift", "mesh": "/abs/lift.stl", "scale": 2, "translation": [1, 2, 3],
       "motion": {"type": "path", "keyframes": [{"time": 0, "translation": [0, 0, 0]},
                                                {"time": 0.5, "translation": [0, 0, 0.1]}]}}]})");
  const Scene s = parse(scene);
  ASSERT_EQ(s.contact.obstacles.size(), 2u);
  const Obstacle& floor = s.contact.obstacles[0];
  EXPECT_EQ(floor.name, "obstacle0");
  EXPECT_EQ(floor.mesh_file, "/base/meshes/floor.obj");
  EXPECT_EQ(floor.scale, 1.0);
  EXPECT_EQ(floor.motion.kind, Motion::Kind::Fixed);
  EXPECT_EQ(floor.key_path, "contact.obstacles[0]");
  const Obstacle& lift = s.contact.obstacles[1];
  EXPECT_EQ(lift.name, "lift");
  EXPECT_EQ(lift.mesh_file, "/abs/lift.stl");
  EXPECT_EQ(lift.scale, 2.0);
  EXPECT_EQ(lift.translation, (std::array<double, 3>{1, 2, 3}));
  EXPECT_EQ(lift.motion.kind, Motion::Kind::Path);
  ASSERT_EQ(lift.motion.path.size(), 2u);
  EXPECT_EQ(lift.motion.path[1], (std::array<double, 4>{0.5, 0, 0, 0.1}));
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

TEST(DefaultScene, IsTheDocumentedContactDrop) {
  const Scene scene = default_scene();
  EXPECT_EQ(scene.source, "<default scene>");
  ASSERT_EQ(scene.materials.size(), 1u);
  EXPECT_EQ(scene.materials[0].E, 1e5);
  EXPECT_EQ(scene.materials[0].nu, 0.4);
  EXPECT_EQ(scene.materials[0].rho, 1000);
  ASSERT_EQ(scene.bodies.size(), 2u);
  const Body& base = scene.bodies[0];
  const Body& cube = scene.bodies[1];
  ASSERT_TRUE(base.box.has_value());
  ASSERT_TRUE(cube.box.has_value());
  EXPECT_EQ(base.box->size, (std::array<double, 3>{0.4, 0.4, 0.1}));
  EXPECT_EQ(base.box->resolution, (std::array<int, 3>{8, 8, 2}));
  EXPECT_EQ(cube.box->size, (std::array<double, 3>{0.2, 0.2, 0.2}));
  EXPECT_EQ(cube.box->resolution, (std::array<int, 3>{6, 6, 6}));
  EXPECT_FALSE(base.kinematic);
  EXPECT_FALSE(cube.kinematic);
  // The base rests just above the ground plane z = 0 (a positive gap, as IPC requires) and
  // the cube starts 0.05 m above the base, a little off its centre (13 mm, 7 mm) so that no cube
  // vertex lands exactly on a base vertex: the symmetric landing has two mirror-image
  // solutions, and which one a run finds would depend on round-off.
  const double base_bottom = base.box->origin[2];
  const double base_top = base_bottom + base.box->size[2];
  EXPECT_GT(base_bottom, 0.0);
  EXPECT_LE(base_bottom, 2e-3);
  EXPECT_NEAR(cube.box->origin[2] - base_top, 0.05, 1e-12);
  const double offset[2] = {0.013, 0.007};
  for (int d = 0; d < 2; ++d) {
    EXPECT_NEAR(cube.box->origin[d] + cube.box->size[d] / 2 - (base.box->origin[d] + base.box->size[d] / 2), offset[d],
                1e-12);
  }
  EXPECT_TRUE(scene.dirichlet.empty());
  EXPECT_EQ(scene.gravity, (std::array<double, 3>{0, 0, -9.81}));
  EXPECT_EQ(scene.dt, 0.01);
  EXPECT_EQ(scene.steps, 40);
  EXPECT_TRUE(scene.contact.enabled);
  EXPECT_EQ(scene.contact.dhat, 1e-3);
  EXPECT_TRUE(scene.contact.dhat_relative);
  EXPECT_TRUE(scene.contact.kappa_adaptive);
  EXPECT_EQ(scene.contact.friction, 0.2);
  ASSERT_EQ(scene.contact.planes.size(), 1u);
  EXPECT_EQ(scene.contact.planes[0].point, (std::array<double, 3>{0, 0, 0}));
  EXPECT_EQ(scene.contact.planes[0].normal, (std::array<double, 3>{0, 0, 1}));
  EXPECT_EQ(scene.output_directory, "output");
  EXPECT_EQ(scene.output_name, "dipc");
}

TEST(BeamScene, IsTheDocumentedCantilever) {
  const Scene scene = beam_scene();
  EXPECT_EQ(scene.source, "<beam scene>");
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
  EXPECT_FALSE(scene.contact.enabled);
  EXPECT_EQ(scene.output_directory, "output");
  EXPECT_EQ(scene.output_name, "dipc");
}

json read_json(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("missing " + path);
  std::ostringstream text;
  text << in.rdbuf();
  return json::parse(text.str());
}

// The example files shipped for users must stay the scenes the program embeds.
TEST(DefaultScene, MatchesTheExampleFile) {
  EXPECT_EQ(read_json(std::string(DIPC_IO_TEST_DATA) + "/default_scene.json"), json::parse(default_scene_json()));
}

TEST(BeamScene, MatchesTheExampleFiles) {
  EXPECT_EQ(read_json(std::string(DIPC_IO_TEST_DATA) + "/beam_scene.json"), json::parse(beam_scene_json()));
  EXPECT_EQ(read_json(std::string(DIPC_SCENES_DIR) + "/default_beam.json"), json::parse(beam_scene_json()));
}

}  // namespace
}  // namespace dipc
