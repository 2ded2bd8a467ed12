// PolyFEM's `common` (io/polyfem_common.hpp), as its example scenes use it: the scene merged
// over the file it names (nested commons too), `patch` applied after, relative paths taken from
// the scene's directory unless the common file gives root_path, and the errors: a missing file,
// a common that includes itself, a patch that does not apply, and a bad key that came from the
// common file (the message names the file). Each test writes its files in a fresh directory.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "io/scene.hpp"

namespace dipc {
namespace {

namespace fs = std::filesystem;

class PolyfemCommon : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string pattern = (fs::temp_directory_path() / "dipc_polyfem_common_XXXXXX").string();
    ASSERT_NE(mkdtemp(pattern.data()), nullptr);
    dir_ = pattern;
    fs::create_directories(dir_ / "base");
    fs::create_directories(dir_ / "scenes");
  }
  void TearDown() override { fs::remove_all(dir_); }

  void write(const std::string& name, const std::string& text) { std::ofstream(dir_ / name) << text; }
  std::string path(const std::string& name) const { return (dir_ / name).lexically_normal().string(); }

  // A scene in scenes/ over base/common.json, with `more` root keys (after a comma).
  Scene read_scene(const std::string& more = "") {
    write("scenes/s.json", R"({"common": "../base/common.json", "geometry": [{"mesh": "a.msh"}],
      "time": {"dt": 0.01, "time_steps": 2}, "contact": {"friction_coefficient": 0.3})" +
                               (more.empty() ? "" : ", " + more) + "}");
    return parse_scene_file(path("scenes/s.json"));
  }

  std::string error_of(const std::string& more = "") {
    try {
      read_scene(more);
    } catch (const SceneError& e) {
      return e.what();
    }
    ADD_FAILURE() << "accepted";
    return "";
  }

  fs::path dir_;
};

const char* kCommon = R"({"contact": {"enabled": true, "dhat": 0.002, "friction_coefficient": 0.1},
  "materials": [{"type": "NeoHookean", "E": 1e6, "nu": 0.4}],
  "solver": {"advanced": {"lump_mass_matrix": true}}})";

TEST_F(PolyfemCommon, SceneKeysOverTheCommonFile) {
  write("base/common.json", kCommon);
  const Scene s = read_scene();
  EXPECT_TRUE(s.contact.enabled);
  EXPECT_EQ(s.contact.dhat, 0.002);    // from the common file
  EXPECT_EQ(s.contact.friction, 0.3);  // the scene's value wins
  EXPECT_TRUE(s.lumped_mass);          // from the common file
  ASSERT_EQ(s.bodies.size(), 1u);
  EXPECT_EQ(s.bodies[0].mesh_file, path("scenes/a.msh"));  // relative to the scene, not the common file
  ASSERT_FALSE(s.notes.empty());
  EXPECT_NE(s.notes[0].find("common: merged: the scene's keys over " + path("base/common.json")), std::string::npos)
      << s.notes[0];
}

TEST_F(PolyfemCommon, PatchAppliesAfterTheMerge) {
  write("base/common.json", kCommon);
  const Scene s = read_scene(R"("patch": [{"op": "replace", "path": "/contact/dhat", "value": 0.003}])");
  EXPECT_EQ(s.contact.dhat, 0.003);
  const std::string e = error_of(R"("patch": [{"op": "remove", "path": "/nothing"}])");
  EXPECT_NE(e.find("s.json: patch: does not apply"), std::string::npos) << e;
}

TEST_F(PolyfemCommon, NestedCommonAndItsRootPath) {
  // base/common.json has a root_path, base/meshes: the scene's mesh and the common file's own
  // common (deeper.json) resolve against it, PolyFEM's rule for a common file that gives one.
  fs::create_directories(dir_ / "base/meshes");
  write("base/meshes/deeper.json", R"({"contact": {"enabled": true, "dhat": 0.004}})");
  write("base/common.json", R"({"common": "deeper.json", "root_path": "meshes",
    "materials": [{"type": "NeoHookean", "E": 1e6, "nu": 0.4}]})");
  const Scene s = read_scene();
  EXPECT_EQ(s.contact.dhat, 0.004);
  EXPECT_EQ(s.bodies[0].mesh_file, path("base/meshes/a.msh"));
  // A root_path that is not a directory is a file, whose directory counts (PolyFEM's rule).
  write("base/common.json", R"({"root_path": "meshes/deeper.json", "common": "deeper.json",
    "materials": [{"type": "NeoHookean", "E": 1e6, "nu": 0.4}]})");
  EXPECT_EQ(read_scene().bodies[0].mesh_file, path("base/meshes/a.msh"));
}

TEST_F(PolyfemCommon, Errors) {
  std::string e = error_of();
  EXPECT_NE(e.find("s.json: common = \"../base/common.json\": " + path("base/common.json") + ": cannot open"),
            std::string::npos)
      << e;
  write("base/common.json", R"({"common": "../scenes/s.json"})");
  e = error_of();
  EXPECT_NE(e.find("common.json: common = \"../scenes/s.json\": " + path("scenes/s.json") + ": includes itself"),
            std::string::npos)
      << e;
  write("base/common.json", R"({"materials": [{"type": "LinearElasticity", "E": 1e6, "nu": 0.4}]})");
  e = error_of();
  EXPECT_NE(e.find("s.json: materials[0].type = \"LinearElasticity\""), std::string::npos) << e;
  EXPECT_NE(e.find("in the scene merged over its common file " + path("base/common.json")), std::string::npos) << e;
  write("base/common.json", R"({"contact": {"dhat": 0.002,)");
  e = error_of();
  EXPECT_NE(e.find(path("base/common.json")), std::string::npos) << e;
}

}  // namespace
}  // namespace dipc
