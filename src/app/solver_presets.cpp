#include "app/solver_presets.hpp"

#include <cstring>
#include <sstream>
#include <stdexcept>

#include "options/dipc_options.hpp"

namespace dipc {

namespace {

// User options that stand for a preset option: when the first is set, the preset's second is
// not inserted.
constexpr std::pair<const char*, const char*> kReplaces[] = {
    {"-snes_lag_preconditioner", "-dipc_pc_reuse"},
    {"-dipc_velocity_tol", "-dipc_velocity_tol_rel"},
};

PetscErrorCode is_set(const std::string& name, bool* set) {
  PetscFunctionBeginUser;
  PetscBool has = PETSC_FALSE;
  PetscCall(PetscOptionsHasName(nullptr, nullptr, name.c_str(), &has));
  *set = has;
  for (const auto& [user, replaced] : kReplaces) {
    if (*set || name != replaced) continue;
    PetscCall(PetscOptionsHasName(nullptr, nullptr, user, &has));
    *set = has;
  }
  PetscFunctionReturn(0);
}

}  // namespace

std::vector<std::pair<std::string, std::string>> preset_options(const SolverPreset& preset) {
  std::vector<std::pair<std::string, std::string>> out;
  std::istringstream lines(preset.text);
  int number = 0;
  for (std::string line; std::getline(lines, line);) {
    ++number;
    std::istringstream words(line.substr(0, line.find('#')));
    std::vector<std::string> w;
    for (std::string word; words >> word;) w.push_back(word);
    if (w.empty()) continue;
    const std::string where = std::string("preset ") + preset.name + ", line " + std::to_string(number) + ": ";
    if (w.size() > 2 || w[0].size() < 2 || w[0][0] != '-')
      throw std::runtime_error(where + "expected \"-option [value]\", got \"" + line + "\"");
    out.emplace_back(w[0], w.size() == 2 ? w[1] : "");
  }
  return out;
}

PetscErrorCode apply_solver_preset(MPI_Comm comm, std::string* applied, std::vector<std::string>* inserted) {
  PetscFunctionBeginUser;
  const std::vector<SolverPreset>& presets = solver_presets();
  std::vector<const char*> names;
  PetscInt chosen = 0;
  for (const SolverPreset& p : presets) {
    if (std::strcmp(p.name, kDefaultPreset) == 0) chosen = static_cast<PetscInt>(names.size());
    names.push_back(p.name);
  }
  PetscOptionsBegin(comm, nullptr, "dipc solver preset", "dipc");
  constexpr const OptionSpec& preset = dipc_option("-dipc_preset");
  PetscCall(PetscOptionsEList(preset.name, preset.help, preset.manual, names.data(),
                              static_cast<PetscInt>(names.size()), names[chosen], &chosen, nullptr));
  PetscOptionsEnd();
  inserted->clear();
  for (const auto& [name, value] : preset_options(presets[chosen])) {
    bool set = false;
    PetscCall(is_set(name, &set));
    if (set) continue;
    PetscCall(PetscOptionsSetValue(nullptr, name.c_str(), value.empty() ? nullptr : value.c_str()));
    inserted->push_back(name);
  }
  *applied = presets[chosen].name;
  PetscFunctionReturn(0);
}

}  // namespace dipc
