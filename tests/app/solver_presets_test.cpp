// The solver presets (-dipc_preset, scenes/solver/presets/*.opts): the embedded files parse and
// agree with the option table, and on small shipped scenes, against a tight reference
// (-dipc_velocity_tol_rel 1e-7 -ksp_rtol 1e-10, a fresh AMG at every iteration), tightening the
// preset (fast -> balanced -> accurate) never makes the error worse beyond noise, and each
// preset's error stays within the bound README "Speed or accuracy" states for it. The error is
// max |u - u_ref| / max |u_ref| over the nodes at the end of the run (the README's bound is on
// the maximum over all output times, which is at least this).
#include <gtest/gtest.h>
#include <petscsys.h>

#include <algorithm>
#include <cstdio>
#include <map>
#include <set>
#include <sstream>

#include "app/option_checks.hpp"
#include "app/run_options.hpp"
#include "app/simulation.hpp"
#include "app/solver_presets.hpp"
#include "displacement_difference.hpp"
#include "io/default_scene.hpp"
#include "support/source_tree.hpp"

namespace dipc {
namespace {

// README, "Speed or accuracy": the largest error each preset may have on the shipped scenes.
const std::map<std::string, double> kStatedBound{{"fast", 1e-3}, {"balanced", 1e-4}, {"accurate", 1e-5}};
// Errors below this are round-off and the order of the presets says nothing about them.
constexpr double kNoiseFloor = 1e-10;
// A tighter preset may end at most this factor above a looser one (different but equally
// converged iterates can land on either side of the reference).
constexpr double kNoiseFactor = 2.0;

TEST(SolverPresets, FilesParseAndAgreeWithTheOptionTable) {
  const std::vector<std::string> names(dipc_option("-dipc_preset").choices.begin(),
                                       dipc_option("-dipc_preset").choices.end());
  ASSERT_EQ(names.size(), solver_presets().size());
  std::set<std::string> first_keys;
  for (std::size_t i = 0; i < names.size(); ++i) {
    const SolverPreset& preset = solver_presets()[i];
    EXPECT_EQ(names[i], preset.name);
    std::set<std::string> keys;
    for (const auto& [name, value] : preset_options(preset)) {
      keys.insert(name);
      for (const OptionSpec& spec : kDipcOptions) {
        if (name == spec.name) {
          EXPECT_EQ(option_value_problem(spec, value.c_str()), "") << preset.name << ": " << name;
        }
      }
    }
    EXPECT_FALSE(keys.empty()) << preset.name;
    // Every preset sets the same options, so that choosing another replaces all of them.
    if (i == 0) first_keys = keys;
    EXPECT_EQ(keys, first_keys) << preset.name << " sets other options than " << solver_presets()[0].name;
  }
  EXPECT_NE(std::find(names.begin(), names.end(), kDefaultPreset), names.end());
}

TEST(SolverPresets, RefusesALineThatIsNotAnOption) {
  const SolverPreset bad{"bad", "# comment\n-ksp_rtol 1e-3\nksp_rtol 1e-3\n"};
  try {
    preset_options(bad);
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("preset bad, line 3"), std::string::npos) << e.what();
  }
}

struct SmallScene {
  const char* name;  // scenes/<name>.json, or "default"
  int steps;
};

// Each runs past its scene's main event: the default cube lands at step 10, boxes_drop's lower
// box at step 20, the roller's block meets the rollers at step 6 (friction: the scene where the
// presets differ most, README "Speed or accuracy"); the beam has no contact.
const SmallScene kScenes[] = {{"default", 12}, {"boxes_drop", 25}, {"roller_squeeze", 8}, {"default_beam", 10}};

RunOptions quiet(int steps) {
  RunOptions o;
  o.steps = steps;
  o.write_output = false;
  o.quiet = true;
  o.report = false;
  return o;
}

// A run with `preset` applied the way the program applies it (apply_solver_preset, then the
// run options read from the database), its options removed afterwards.
PetscErrorCode run_preset(const Scene& scene, const std::string& preset, int steps, RunResult* result) {
  PetscFunctionBeginUser;
  PetscCall(PetscOptionsSetValue(nullptr, "-dipc_preset", preset.c_str()));
  RunOptions options = quiet(steps);
  std::vector<std::string> inserted;
  PetscCall(apply_solver_preset(PETSC_COMM_WORLD, &options.preset, &inserted));
  PetscCall(read_run_options(PETSC_COMM_WORLD, scene, &options));
  options.steps = steps;
  PetscCall(run_scene(scene, PETSC_COMM_WORLD, options, result));
  for (const std::string& name : inserted) PetscCall(PetscOptionsClearValue(nullptr, name.c_str()));
  PetscCall(PetscOptionsClearValue(nullptr, "-dipc_preset"));
  PetscFunctionReturn(0);
}

class PresetAccuracy : public ::testing::TestWithParam<SmallScene> {};

TEST_P(PresetAccuracy, TighterIsNeverWorseAndWithinTheStatedBound) {
  const SmallScene& s = GetParam();
  const Scene scene = std::string(s.name) == "default"
                          ? default_scene()
                          : parse_scene_file(dipc::test::source_dir() + "/scenes/" + s.name + ".json");
  RunResult reference, rest;
  PetscOptionsSetValue(nullptr, "-ksp_rtol", "1e-10");
  PetscOptionsSetValue(nullptr, "-dipc_pc_reuse", "0");
  RunOptions tight = quiet(s.steps);
  tight.velocity_tol_rel = 1e-7;
  ASSERT_EQ(run_scene(scene, PETSC_COMM_WORLD, tight, &reference), 0);
  PetscOptionsClearValue(nullptr, "-ksp_rtol");
  PetscOptionsClearValue(nullptr, "-dipc_pc_reuse");
  ASSERT_TRUE(reference.failure.empty()) << reference.failure;
  RunOptions zero = quiet(s.steps);
  zero.setup_only = true;
  ASSERT_EQ(run_scene(scene, PETSC_COMM_WORLD, zero, &rest), 0);

  std::map<std::string, double> error;
  for (const SolverPreset& preset : solver_presets()) {
    RunResult r;
    ASSERT_EQ(run_preset(scene, preset.name, s.steps, &r), 0);
    ASSERT_TRUE(r.failure.empty()) << preset.name << ": " << r.failure;
    const DisplacementDifference d = displacement_difference(reference, r, rest);
    ASSERT_GT(d.max_displacement, 0.0);
    error[preset.name] = d.relative();
    std::printf("%-14s %-9s error %.3e, %lld Newton, %lld CG iterations\n", s.name, preset.name, error[preset.name],
                r.newton_iterations, r.linear_iterations);
  }
  for (const auto& [name, bound] : kStatedBound) EXPECT_LE(error.at(name), bound) << s.name << ", " << name;
  EXPECT_LE(error.at("balanced"), kNoiseFactor * error.at("fast") + kNoiseFloor) << s.name;
  EXPECT_LE(error.at("accurate"), kNoiseFactor * error.at("balanced") + kNoiseFloor) << s.name;
}

INSTANTIATE_TEST_SUITE_P(Small, PresetAccuracy, ::testing::ValuesIn(kScenes),
                         [](const auto& info) { return std::string(info.param.name); });

}  // namespace
}  // namespace dipc
