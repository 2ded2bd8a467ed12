// Bad input end to end: each malformed scene, mesh, option or options file makes `dipc` exit
// with status 1 and one clear message that names the file and the key, element, node, bodies or
// option — and no PETSc error trace — on 1 and 2 ranks.
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

namespace {

struct Outcome {
  int status;
  std::string output;
};

// `dipc <data file> -dipc_no_output -dipc_quiet <extra>` on `ranks` ranks (mpiexec for 2).
Outcome run_dipc(const std::string& scene, const std::string& extra = "", int ranks = 1) {
  const std::string launcher = ranks > 1 ? std::string(DIPC_MPIEXEC) + " -n " + std::to_string(ranks) + " " : "";
  const std::string cmd = launcher + DIPC_BINARY + " " + DIPC_SOURCE_DIR + "/tests/app/data/" + scene +
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
  const char* name;   // the test's name
  const char* scene;  // under tests/app/data/
  std::string extra;  // more arguments
  std::vector<std::string> expected;  // substrings of the message
};

const std::string data_dir = std::string(DIPC_SOURCE_DIR) + "/tests/app/data/";

class InputErrors : public ::testing::TestWithParam<std::tuple<BadInput, int>> {};

TEST_P(InputErrors, ExitOneWithAClearMessage) {
  const auto& [c, ranks] = GetParam();
  const Outcome o = run_dipc(c.scene, c.extra, ranks);
  EXPECT_EQ(o.status, 1) << o.output;
  EXPECT_NE(o.output.find("dipc: error: "), std::string::npos) << o.output;
  for (const auto& s : c.expected) EXPECT_NE(o.output.find(s), std::string::npos) << "missing '" << s << "' in:\n" << o.output;
  EXPECT_EQ(o.output.find("PETSC ERROR"), std::string::npos) << o.output;
}

INSTANTIATE_TEST_SUITE_P(
    Table, InputErrors,
    ::testing::Combine(
        ::testing::Values(
            BadInput{"bad_syntax", "bad_syntax.json", "", {"bad_syntax.json", "line 3"}},
            BadInput{"unknown_key", "unknown_key.json", "", {"unknown_key.json", "gravty"}},
            BadInput{"nu_half", "nu_half.json", "", {"nu_half.json", "materials[0].nu", "(-1, 0.5)"}},
            BadInput{"negative_dt", "negative_dt.json", "", {"negative_dt.json", "time.dt"}},
            BadInput{"inverted_mesh", "inverted_mesh.json", "", {"inverted.msh", "element 1", "inverted"}},
            BadInput{"nan_mesh", "nan_mesh.json", "", {"nan_coordinate.msh", "node 1"}},
            BadInput{"missing_mesh", "missing_mesh.json", "", {"missing.msh"}},
            BadInput{"unknown_selection", "unknown_selection.json", "", {"unknown_selection.json", "cube.left"}},
            BadInput{"does_not_exist", "does_not_exist.json", "", {"does_not_exist.json"}},
            BadInput{"scene_is_a_directory", "", "", {"is a directory"}},
            BadInput{"intersecting_bodies", "intersecting_bodies.json", "",
                     {"not intersection-free", "crosses triangle", "\"upper\"", "\"lower\""}},
            BadInput{"touching_bodies", "touching_bodies.json", "",
                     {"not intersection-free", "touch", "\"upper\"", "\"lower\""}},
            BadInput{"nested_bodies", "nested_bodies.json", "", {"body \"inner\" lies inside body \"outer\""}},
            BadInput{"obstacle_missing", "obstacle_missing.json", "",
                     {"obstacle_missing.json", "contact.obstacles[0].mesh", "missing_floor.obj", "cannot open"}},
            BadInput{"obstacle_degenerate_face", "obstacle_degenerate.json", "",
                     {"contact.obstacles[0].mesh", "obstacle_degenerate.obj:10:", "degenerate triangle"}},
            BadInput{"obstacle_degenerate_stl_facet", "obstacle_degenerate_stl.json", "",
                     {"contact.obstacles[0].mesh", "obstacle_degenerate.stl: facet 1", "degenerate triangle"}},
            BadInput{"obstacle_nan", "obstacle_nan.json", "",
                     {"contact.obstacles[0].mesh", "obstacle_nan.obj:4:", "non-finite"}},
            BadInput{"obstacle_crossing", "obstacle_crossing.json", "",
                     {"not intersection-free", "crosses triangle", "of obstacle \"floor\" (", "obstacle_floor.obj:", "\"cube\""}},
            BadInput{"obstacle_on_cuda", "obstacle_floor.json", "-dipc_backend cuda",
                     {"-dipc_backend cuda", "obstacles", "CPU only"}},
            BadInput{"negative_steps", "small_box.json", "-dipc_steps -1", {"-dipc_steps -1"}},
            BadInput{"zero_steps", "small_box.json", "-dipc_steps 0", {"-dipc_steps 0"}},
            BadInput{"non_numeric_steps", "small_box.json", "-dipc_steps abc", {"-dipc_steps abc", "not an integer"}},
            BadInput{"half_steps", "small_box.json", "-dipc_steps 2.5", {"-dipc_steps 2.5", "not an integer"}},
            BadInput{"zero_refine", "small_box.json", "-dipc_refine 0", {"-dipc_refine 0"}},
            BadInput{"negative_velocity_tol", "small_box.json", "-dipc_velocity_tol -1", {"-dipc_velocity_tol -1"}},
            BadInput{"zero_velocity_tol_rel", "small_box.json", "-dipc_velocity_tol_rel 0", {"-dipc_velocity_tol_rel 0"}},
            BadInput{"nan_velocity_tol", "small_box.json", "-dipc_velocity_tol nan", {"-dipc_velocity_tol nan"}},
            BadInput{"negative_gpu_elements", "small_box.json", "-dipc_auto_gpu_elements -5",
                     {"-dipc_auto_gpu_elements -5"}},
            BadInput{"unknown_backend", "small_box.json", "-dipc_backend foo", {"-dipc_backend foo", "cpu, cuda, auto"}},
            BadInput{"non_boolean_flag", "small_box.json", "-dipc_pc_reuse abc", {"-dipc_pc_reuse abc"}},
            BadInput{"empty_output", "small_box.json", "-dipc_output", {"-dipc_output needs a value"}},
            BadInput{"unknown_option", "small_box.json", "-dipc_stepz 3", {"unknown option -dipc_stepz", "-dipc_steps?"}},
            BadInput{"misspelt_flag", "small_box.json", "-dipc_check_invariant",
                     {"unknown option -dipc_check_invariant ", "-dipc_check_invariants?"}},
            BadInput{"missing_options_file", "small_box.json", "-options_file " + data_dir + "none.opts",
                     {"-options_file", "none.opts: no such file"}},
            BadInput{"missing_nested_options_file", "small_box.json", "-options_file " + data_dir + "missing_nested.opts",
                     {"does_not_exist.opts (named in", "missing_nested.opts): no such file"}}),
        ::testing::Values(1, 2)),
    [](const auto& info) {
      return std::string(std::get<0>(info.param).name) + "_np" + std::to_string(std::get<1>(info.param));
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

// A step that step recovery cannot take (no room to halve: -dipc_dt_min = dt, and a 100 m/s
// impact that Newton cannot resolve in one 5 ms step) stops the run with exit status 2 and a
// message naming the step, the time and the reason; the output written so far stays readable
// (the XDMF lists the initial state).
TEST(StepFailure, RecoveryThatRunsOutExitsWithStatusTwo) {
  for (int ranks : {1, 2}) {
    const std::string dir = "recovery_runs_out_np" + std::to_string(ranks);
    const std::string launcher = ranks > 1 ? std::string(DIPC_MPIEXEC) + " -n 2 " : "";
    const std::string cmd = launcher + DIPC_BINARY + " " + data_dir + "impact_100ms.json -dipc_quiet -dipc_dt_min 0.005 "
                            "-dipc_output " + dir + " 2>&1";
    FILE* pipe = popen(cmd.c_str(), "r");
    ASSERT_NE(pipe, nullptr);
    std::string output;
    std::array<char, 4096> buf;
    while (std::fgets(buf.data(), buf.size(), pipe)) output += buf.data();
    const int raw = pclose(pipe);
    ASSERT_TRUE(WIFEXITED(raw)) << output;
    EXPECT_EQ(WEXITSTATUS(raw), 2) << output;
    for (const char* s : {"dipc: error: step 1 (t = 0", "Newton failed", "step recovery ran out"})
      EXPECT_NE(output.find(s), std::string::npos) << "missing '" << s << "' in:\n" << output;
    EXPECT_EQ(output.find("PETSC ERROR"), std::string::npos) << output;
    std::ifstream xmf(dir + "/impact.xmf");
    std::stringstream text;
    text << xmf.rdbuf();
    EXPECT_NE(text.str().find("<Time Value=\"0\""), std::string::npos) << dir << "/impact.xmf:\n" << text.str();
  }
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
