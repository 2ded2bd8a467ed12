// The listener of tests/mpi_test_main.cpp: options a test leaves in PETSc's database (here on
// purpose, as a test that fails an ASSERT before clearing them would) are gone in the next
// test, and options that were there before the test (set by the suite) are back. GoogleTest
// runs the tests of a file in the order they are written.
#include <gtest/gtest.h>
#include <petscsys.h>

namespace {

bool has(const char* name) {
  PetscBool set = PETSC_FALSE;
  EXPECT_EQ(PetscOptionsHasName(nullptr, nullptr, name, &set), 0);
  return set;
}

class OptionsRestore : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { PetscOptionsSetValue(nullptr, "-restore_test_suite_option", "1"); }
};

TEST_F(OptionsRestore, ATestLeavesOptionsBehind) {
  ASSERT_TRUE(has("-restore_test_suite_option"));
  PetscOptionsSetValue(nullptr, "-restore_test_left_behind", "1");
  PetscOptionsClearValue(nullptr, "-restore_test_suite_option");
  EXPECT_TRUE(has("-restore_test_left_behind"));
}

TEST_F(OptionsRestore, TheNextTestSeesTheDatabaseAsBefore) {
  EXPECT_FALSE(has("-restore_test_left_behind"));
  EXPECT_TRUE(has("-restore_test_suite_option"));
}

TEST(OptionsRestoreAfterSuite, TheSuitesOptionsAreGoneToo) { EXPECT_FALSE(has("-restore_test_suite_option")); }

}  // namespace
