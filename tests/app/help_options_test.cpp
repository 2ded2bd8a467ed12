// `dipc -help` lists every -dipc_ option that the code reads, PETSc-style, and then exits: the
// options are found by scanning the sources (every string literal in src/ that starts with
// "-dipc_": the options read, and the messages that name them) and in the option table
// (options/dipc_options.hpp), so an option added without a help entry or a table row fails here.
// docs/options.md's table lists the same options as the option table.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>

#include "app/option_checks.hpp"
#include "io/scene.hpp"
#include "support/source_tree.hpp"

namespace {

struct Outcome {
  int status;
  std::string output;
};

Outcome run_dipc(const std::string& arguments) {
  const std::string cmd = std::string(DIPC_BINARY) + " " + arguments + " 2>&1";
  Outcome o{-1, ""};
  FILE* pipe = popen(cmd.c_str(), "r");
  if (!pipe) return o;
  std::array<char, 4096> buf;
  while (std::fgets(buf.data(), buf.size(), pipe)) o.output += buf.data();
  const int raw = pclose(pipe);
  o.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  return o;
}

// The -dipc_ names at the start of a string literal in the sources under src/.
std::set<std::string> options_in_sources() {
  const std::regex literal("\"(-dipc_[a-z0-9_]*[a-z0-9])");
  std::set<std::string> names;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(dipc::test::source_path("src"))) {
    const std::string ext = entry.path().extension().string();
    if (!entry.is_regular_file() || (ext != ".cpp" && ext != ".hpp" && ext != ".cu" && ext != ".cuh" && ext != ".in"))
      continue;
    std::ifstream in(entry.path());
    const std::string text((std::istreambuf_iterator<char>(in)), {});
    for (std::sregex_iterator m(text.begin(), text.end(), literal), end; m != end; ++m) names.insert((*m)[1]);
  }
  return names;
}

// -help's entry lines for -dipc_ options: name -> the line.
std::map<std::string, std::string> help_entries(const std::string& output) {
  const std::regex entry(R"(^\s+(-dipc_[a-z0-9_]+)[:\s])");
  std::map<std::string, std::string> lines;
  std::istringstream in(output);
  for (std::string line; std::getline(in, line);) {
    std::smatch m;
    if (std::regex_search(line, m, entry)) lines[m[1]] = line;
  }
  return lines;
}

class HelpOptions : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    help_ = new Outcome(run_dipc(dipc::test::source_path("tests/app/data/cube_good.json") + " -help"));
  }
  static void TearDownTestSuite() { delete help_; }
  static Outcome* help_;
};
Outcome* HelpOptions::help_ = nullptr;

TEST_F(HelpOptions, PrintsAndExits) {
  EXPECT_EQ(help_->status, 0) << help_->output;
  // No run: no step line, no run header, no timing table, no output written.
  for (const char* run_text : {"step     1", "dipc 0.1.0 |", "phase (max over ranks)", "steps written to"})
    EXPECT_EQ(help_->output.find(run_text), std::string::npos) << "-help printed '" << run_text << "':\n"
                                                               << help_->output;
  // PETSc's own options are listed too: the solvers were set up.
  for (const char* petsc : {"-snes_type", "-ksp_type", "-pc_type"})
    EXPECT_NE(help_->output.find(petsc), std::string::npos) << petsc;
}

TEST_F(HelpOptions, ListsEveryOptionTheSourcesAndTheTableName) {
  const std::set<std::string> in_sources = options_in_sources();
  const std::map<std::string, std::string> listed = help_entries(help_->output);
  std::set<std::string> in_table;
  for (const dipc::OptionSpec& spec : dipc::kDipcOptions) in_table.insert(spec.name);
  // The scan is not vacuous: it finds the table's rows (dipc_options.hpp is under src/) and the
  // messages that name options.
  EXPECT_TRUE(in_sources.count("-dipc_steps") && in_sources.count("-dipc_pc_reuse") &&
              in_sources.size() >= in_table.size());
  for (const std::string& name : in_sources) {
    EXPECT_TRUE(listed.count(name)) << name << " appears in src/ but not in -help";
    EXPECT_TRUE(in_table.count(name)) << name << " appears in src/ but has no row in options/dipc_options.hpp";
  }
  for (const std::string& name : in_table) EXPECT_TRUE(listed.count(name)) << name << " (table) is not in -help";
  for (const auto& [name, line] : listed) EXPECT_TRUE(in_table.count(name)) << name << " (-help) has no table row";
}

// Every option of the table has one line in docs/options.md's table (the first column, which may
// name several options: "`-dipc_no_output`, `-dipc_quiet`"), and that table names no other option;
// `-dipc_mixed_s_*` there is a prefix of PETSc options, not a dipc option.
TEST(OptionsDocument, ListsTheOptionsOfTheTable) {
  std::ifstream in(dipc::test::source_path("docs/options.md"));
  ASSERT_TRUE(in) << "docs/options.md";
  const std::regex name("`(-dipc_[a-z0-9_]*[a-z0-9])`");
  std::set<std::string> documented;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("| `-dipc_", 0) != 0) continue;
    const std::string first_column = line.substr(1, line.find('|', 1) - 1);
    for (std::sregex_iterator m(first_column.begin(), first_column.end(), name), end; m != end; ++m)
      EXPECT_TRUE(documented.insert((*m)[1]).second) << (*m)[1] << " has two rows in docs/options.md";
  }
  std::set<std::string> in_table;
  for (const dipc::OptionSpec& spec : dipc::kDipcOptions) in_table.insert(spec.name);
  for (const std::string& option : in_table)
    EXPECT_TRUE(documented.count(option)) << option << " (options/dipc_options.hpp) is not in docs/options.md";
  for (const std::string& option : documented)
    EXPECT_TRUE(in_table.count(option)) << option << " (docs/options.md) is not an option of options/dipc_options.hpp";
}

// PETSc-style entries: a help text, a manual section in the parentheses (not an empty "()"),
// and a real default, not a sentinel (-1) or an empty string.
TEST_F(HelpOptions, EntriesHaveHelpManualSectionAndRealDefaults) {
  const std::map<std::string, std::string> listed = help_entries(help_->output);
  ASSERT_FALSE(listed.empty()) << help_->output;
  const std::regex manual(R"(\([A-Za-z][A-Za-z_:]*\)\s*$)");
  for (const auto& [name, line] : listed) {
    EXPECT_TRUE(std::regex_search(line, manual)) << "no manual section: " << line;
    EXPECT_EQ(line.find("<-1"), std::string::npos) << "sentinel default: " << line;
    EXPECT_EQ(line.find("<now -1 "), std::string::npos) << "sentinel default: " << line;
    EXPECT_EQ(line.find("<now  :"), std::string::npos) << "empty default: " << line;
  }
}

// The defaults that are the scene's show the scene's values (cube_good.json: 2 steps of 0.01,
// output in "output"), and the Newton tolerance is velocity_tol_rel x the mesh diagonal.
TEST_F(HelpOptions, SceneDefaultsAreTheScenes) {
  const std::map<std::string, std::string> listed = help_entries(help_->output);
  const dipc::Scene scene = dipc::parse_scene_file(dipc::test::source_path("tests/app/data/cube_good.json"));
  char dt_min[64];
  std::snprintf(dt_min, sizeof dt_min, "<%g : %g>", scene.dt / 1024, scene.dt / 1024);
  EXPECT_NE(listed.at("-dipc_steps").find("<now " + std::to_string(scene.steps) + " :"), std::string::npos)
      << listed.at("-dipc_steps");
  EXPECT_NE(listed.at("-dipc_output").find("<now " + scene.output_directory + " :"), std::string::npos)
      << listed.at("-dipc_output");
  EXPECT_NE(listed.at("-dipc_dt_min").find(dt_min), std::string::npos) << listed.at("-dipc_dt_min");
  // -dipc_velocity_tol: a positive number (the diagonal is the mesh's, not the scene file's).
  std::smatch m;
  const std::string& tol = listed.at("-dipc_velocity_tol");
  ASSERT_TRUE(std::regex_search(tol, m, std::regex(R"(<([0-9.e+-]+) :)"))) << tol;
  EXPECT_GT(std::stod(m[1]), 0) << tol;
  // Options given on the command line show as the current value.
  const Outcome given = run_dipc(dipc::test::source_path("tests/app/data/cube_good.json") + " -help -dipc_steps 7");
  EXPECT_NE(help_entries(given.output)["-dipc_steps"].find("<now 7 : formerly " + std::to_string(scene.steps) + ">"),
            std::string::npos)
      << given.output;
}

}  // namespace
