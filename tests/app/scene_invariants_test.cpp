// Every shipped contact scene, every step, with the invariants checked after each step (no
// inverted element, no edge–triangle crossing, positive minimum distance), on the ranks of the
// test's communicator (CTest runs it on 1 and 2 ranks).
#include <gtest/gtest.h>

#include <string>

#include "app/simulation.hpp"
#include "support/source_tree.hpp"

namespace dipc {
namespace {

class SceneInvariants : public ::testing::TestWithParam<std::string> {};

TEST_P(SceneInvariants, EveryStepKeepsTheInvariants) {
  const std::string name = GetParam();
  const Scene scene = name == "default" ? default_scene()
                                        : parse_scene_file(dipc::test::source_dir() + "/scenes/" + name + ".json");
  ASSERT_TRUE(scene.contact.enabled) << name << " is not a contact scene";
  RunOptions options;
  options.write_output = false;
  options.quiet = true;
  options.report = false;
  options.check_invariants = true;
  RunResult result;
  ASSERT_EQ(run_scene(scene, PETSC_COMM_WORLD, options, &result), 0);
  EXPECT_TRUE(result.failure.empty()) << name << ": " << result.failure;
  EXPECT_EQ(result.steps_taken, scene.steps);
  EXPECT_GT(result.max_contact_pairs, 0) << name << ": nothing ever touched";
}

INSTANTIATE_TEST_SUITE_P(Shipped, SceneInvariants,
                         ::testing::Values("default", "boxes_drop", "roller_squeeze", "fast_impact", "friction_stack",
                                           "block_on_plane", "box_on_obj_ramp", "funnel_drop", "obj_rollers"),
                         [](const auto& info) { return info.param; });

}  // namespace
}  // namespace dipc
