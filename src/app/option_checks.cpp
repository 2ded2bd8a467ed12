#include "app/option_checks.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <vector>

#include "app/options_files.hpp"
#include "io/collective_error.hpp"

namespace dipc {

namespace {

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// strtol/strtod accept a prefix of the string; a value must be a number from end to end.
bool parse_integer(const char* value, long* out) {
  char* end = nullptr;
  errno = 0;
  *out = std::strtol(value, &end, 10);
  return end != value && *end == '\0' && errno == 0 && *out >= INT_MIN && *out <= INT_MAX;
}

// An optional sign and decimal digits only: an integer, whether or not it fits.
bool all_digits(const char* value) {
  const char* digits = value + (*value == '-' || *value == '+');
  return *digits && std::all_of(digits, digits + std::strlen(digits),
                                [](char c) { return std::isdigit(static_cast<unsigned char>(c)); });
}

bool parse_real(const char* value, double* out) {
  char* end = nullptr;
  errno = 0;
  *out = std::strtod(value, &end);
  return end != value && *end == '\0' && errno == 0 && std::isfinite(*out);
}

std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = up;
    }
  }
  return row[b.size()];
}

// The options PETSc has not yet been asked for, as ("-name", value or null). Reading this list
// marks nothing as used.
std::vector<std::pair<std::string, const char*>> unused_options(std::vector<std::string>* storage) {
  PetscInt n = 0;
  char **names = nullptr, **values = nullptr;
  if (PetscOptionsLeftGet(nullptr, &n, &names, &values)) throw std::runtime_error("PetscOptionsLeftGet failed");
  std::vector<std::pair<std::string, const char*>> out;
  storage->clear();
  for (PetscInt i = 0; i < n; ++i) storage->push_back(values[i] ? values[i] : "");
  for (PetscInt i = 0; i < n; ++i) {
    const std::string name = names[i][0] == '-' ? names[i] : std::string("-") + names[i];
    out.emplace_back(lower(name), values[i] ? (*storage)[i].c_str() : nullptr);
  }
  PetscOptionsLeftRestore(nullptr, &n, &names, &values);
  return out;
}

bool is_dipc_option(const std::string& name) { return name.rfind("-dipc_", 0) == 0; }

// The program's arguments after its name, as PetscInitialize received them.
std::vector<std::string> command_line() {
  int argc = 0;
  char** argv = nullptr;
  if (PetscGetArgs(&argc, &argv) || !argv) return {};
  return {argv + 1, argv + argc};
}

}  // namespace

std::string option_value_problem(const OptionSpec& spec, const char* value) {
  const std::string name = spec.name;
  if (spec.kind == OptionKind::flag) {
    if (!value || !*value) return "";
    for (const char* word : {"1", "0", "true", "false", "yes", "no", "on", "off"})
      if (lower(value) == word) return "";
    return name + " " + value + ": must be true or false (or 1/0, yes/no, on/off), or no value for true";
  }
  if (!value || !*value) return name + " needs a value";
  const std::string given = name + " " + value + ": ";
  switch (spec.kind) {
    case OptionKind::integer: {
      long v;
      if (!parse_integer(value, &v))
        return given +
               (all_digits(value) ? "out of range (at most " + std::to_string(INT_MAX) + ")" : "not an integer");
      if (v < spec.min) return given + "must be an integer >= " + std::to_string(long(spec.min));
      return "";
    }
    case OptionKind::real: {
      double v;
      if (!parse_real(value, &v)) return given + "not a finite number";
      if (!(v > spec.min))
        return given + (spec.min == 0 ? std::string("must be > 0") : "must be > " + std::to_string(spec.min));
      if (!(v < spec.max)) return given + "must be < " + std::to_string(spec.max);
      return "";
    }
    case OptionKind::choice: {
      for (const char* choice : spec.choices)
        if (std::string(value) == choice) return "";
      std::string list;
      for (const char* choice : spec.choices) list += (list.empty() ? "" : ", ") + std::string(choice);
      return given + "must be one of " + list;
    }
    default: return "";
  }
}

void check_option_values() {
  std::vector<std::string> storage;
  for (const auto& [name, value] : unused_options(&storage))
    for (const OptionSpec& spec : kDipcOptions)
      if (name == spec.name) {
        const std::string problem = option_value_problem(spec, value);
        if (!problem.empty()) throw std::runtime_error(problem);
      }
}

std::string closest_option(const std::string& name) {
  std::string best;
  std::size_t best_distance = 4;  // suggest only names at most 3 edits away
  for (const OptionSpec& spec : kDipcOptions) {
    const std::size_t d = edit_distance(lower(name), spec.name);
    if (d < best_distance) best = spec.name, best_distance = d;
  }
  return best;
}

void check_no_unknown_options(MPI_Comm comm) {
  std::vector<std::string> storage;
  std::string message;
  for (const auto& entry : unused_options(&storage)) {
    const std::string& name = entry.first;
    if (!is_dipc_option(name)) continue;
    message += (message.empty() ? "unknown option " : "; unknown option ") + name;
    const std::string file = options_file_holding(name, command_line(), std::getenv("PETSC_OPTIONS"));
    if (!file.empty()) message += " in options file " + file;
    const std::string suggestion = closest_option(name);
    if (!suggestion.empty()) message += " (did you mean " + suggestion + "?)";
  }
  throw_if_failed_anywhere(comm, message);
}

}  // namespace dipc
