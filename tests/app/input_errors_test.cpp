// Bad input end to end: each malformed scene or mesh makes `dipc` exit non-zero with one clear
// message that names the file and the key, element or node — and no PETSc error trace.
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <string>

namespace {

struct Outcome {
  int status;
  std::string output;
};

Outcome run_dipc(const std::string& scene, const std::string& extra = "") {
  const std::string cmd = std::string(DIPC_BINARY) + " " + DIPC_SOURCE_DIR + "/tests/app/data/" + scene +
                          " -dipc_no_output -dipc_quiet " + extra + " 2>&1";
  Outcome o{-1, ""};
  FILE* pipe = popen(cmd.c_str(), "r");
  if (!pipe) return o;
  std::array<char, 4096> buf;
  while (std::fgets(buf.data(), buf.size(), pipe)) o.output += buf.data();
  const int raw = pclose(pipe);
  o.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  return o;
}

struct BadInput {
  const char* scene;
  std::vector<std::string> expected;  // substrings of the message
};

class InputErrors : public ::testing::TestWithParam<BadInput> {};

TEST_P(InputErrors, ExitNonZeroWithAClearMessage) {
  const BadInput& c = GetParam();
  const Outcome o = run_dipc(c.scene);
  EXPECT_NE(o.status, 0) << o.output;
  EXPECT_NE(o.output.find("dipc: error: "), std::string::npos) << o.output;
  for (const auto& s : c.expected) EXPECT_NE(o.output.find(s), std::string::npos) << "missing '" << s << "' in:\n" << o.output;
  EXPECT_EQ(o.output.find("PETSC ERROR"), std::string::npos) << o.output;
}

INSTANTIATE_TEST_SUITE_P(
    Table, InputErrors,
    ::testing::Values(BadInput{"bad_syntax.json", {"bad_syntax.json", "line 3"}},
                      BadInput{"unknown_key.json", {"unknown_key.json", "gravty"}},
                      BadInput{"nu_half.json", {"nu_half.json", "materials[0].nu", "(-1, 0.5)"}},
                      BadInput{"negative_dt.json", {"negative_dt.json", "time.dt"}},
                      BadInput{"inverted_mesh.json", {"inverted.msh", "element 1", "inverted"}},
                      BadInput{"nan_mesh.json", {"nan_coordinate.msh", "node 1"}},
                      BadInput{"missing_mesh.json", {"missing.msh"}},
                      BadInput{"unknown_selection.json", {"unknown_selection.json", "cube.left"}},
                      BadInput{"does_not_exist.json", {"does_not_exist.json"}},
                      BadInput{"intersecting_bodies.json",
                               {"not intersection-free", "crosses triangle", "\"upper\"", "\"lower\""}},
                      BadInput{"touching_bodies.json", {"not intersection-free", "touch"}}),
    [](const auto& info) {
      std::string n = info.param.scene;
      return n.substr(0, n.find('.'));
    });

TEST(InputErrors, GoodMeshRuns) {
  const Outcome o = run_dipc("cube_good.json");
  EXPECT_EQ(o.status, 0) << o.output;
}

// -options_file reaches PETSc: the shipped GAMG options replace the BoomerAMG default.
TEST(Options, OptionsFileIsRead) {
  const Outcome o = run_dipc("cube_good.json", std::string("-options_file ") + DIPC_SOURCE_DIR +
                                                   "/scenes/solver/gamg.opts -snes_view");
  EXPECT_EQ(o.status, 0) << o.output;
  EXPECT_NE(o.output.find("type: gamg"), std::string::npos) << o.output;
  const Outcome d = run_dipc("cube_good.json", "-snes_view");
  EXPECT_NE(d.output.find("HYPRE BoomerAMG"), std::string::npos) << d.output;
}

// -help lists the dipc options with their defaults and stops before the first step.
TEST(Options, HelpListsDipcOptions) {
  const Outcome o = run_dipc("cube_good.json", "-help");
  EXPECT_EQ(o.status, 0) << o.output;
  for (const char* opt : {"-dipc_velocity_tol", "-dipc_steps", "-dipc_output", "-snes_type", "-ksp_type"})
    EXPECT_NE(o.output.find(opt), std::string::npos) << opt;
  EXPECT_EQ(o.output.find("step     1"), std::string::npos) << "-help must not run steps";
}

}  // namespace
