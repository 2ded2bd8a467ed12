#include "app/options_files.hpp"

#include <strings.h>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace dipc {

namespace {

// PETSc compares option names without regard to case.
bool is_options_file_key(const std::string& token) { return strcasecmp(token.c_str(), "-options_file") == 0; }

// Whitespace-separated tokens of an options file, without the comments PETSc strips ('#' to
// the end of the line).
std::vector<std::string> file_tokens(std::ifstream& in) {
  std::vector<std::string> tokens;
  for (std::string line; std::getline(in, line);) {
    std::istringstream words(line.substr(0, line.find('#')));
    for (std::string w; words >> w;) tokens.push_back(w);
  }
  return tokens;
}

// Checks the files named after each -options_file in `tokens`, and those they name in turn.
// `depth` stops a file that names itself.
std::string check_tokens(const std::vector<std::string>& tokens, const std::string& where, int depth) {
  for (std::size_t i = 0; i < tokens.size(); ++i) {
    if (!is_options_file_key(tokens[i])) continue;
    if (i + 1 == tokens.size()) return "-options_file" + where + " needs a file name";
    const std::string& name = tokens[++i];
    if (name.find("${") != std::string::npos || name[0] == '~') continue;
    const std::string given = "-options_file " + name + where + ": ";
    std::error_code ec;
    if (!std::filesystem::exists(name, ec)) return given + "no such file";
    if (std::filesystem::is_directory(name, ec)) return given + "is a directory, not an options file";
    std::ifstream in(name);
    if (!in) return given + "cannot be opened";
    if (depth >= 16) return given + "options files nest more than 16 deep (does one name itself?)";
    const std::string problem = check_tokens(file_tokens(in), " (named in " + name + ")", depth + 1);
    if (!problem.empty()) return problem;
  }
  return "";
}

// The options file among those that `tokens` name, and those these name in turn, whose own
// tokens hold `option` (compared without regard to case, as PETSc does); "" when none does.
// Files that cannot be read are passed over: options_file_problem() has reported them.
std::string file_holding(const std::vector<std::string>& tokens, const std::string& option, int depth) {
  if (depth >= 16) return "";
  for (std::size_t i = 0; i + 1 < tokens.size(); ++i) {
    if (!is_options_file_key(tokens[i])) continue;
    const std::string& name = tokens[++i];
    std::ifstream in(name);
    if (!in) continue;
    const std::vector<std::string> inner = file_tokens(in);
    for (const std::string& t : inner)
      if (strcasecmp(t.c_str(), option.c_str()) == 0) return name;
    const std::string nested = file_holding(inner, option, depth + 1);
    if (!nested.empty()) return nested;
  }
  return "";
}

}  // namespace

std::string options_file_holding(const std::string& option, const std::vector<std::string>& args,
                                 const char* petsc_options) {
  if (petsc_options) {
    std::istringstream words(petsc_options);
    std::vector<std::string> tokens;
    for (std::string w; words >> w;) tokens.push_back(w);
    const std::string file = file_holding(tokens, option, 0);
    if (!file.empty()) return file;
  }
  return file_holding(args, option, 0);
}

std::string options_file_problem(const std::vector<std::string>& args, const char* petsc_options) {
  if (petsc_options) {
    std::istringstream words(petsc_options);
    std::vector<std::string> tokens;
    for (std::string w; words >> w;) tokens.push_back(w);
    const std::string problem = check_tokens(tokens, " (in PETSC_OPTIONS)", 0);
    if (!problem.empty()) return problem;
  }
  return check_tokens(args, "", 0);
}

}  // namespace dipc
