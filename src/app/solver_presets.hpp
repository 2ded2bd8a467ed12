// -dipc_preset fast | balanced | accurate: named sets of solver options (issue 12). Each preset
// is a plain options file, scenes/solver/presets/<name>.opts, read by CMake and compiled into
// the program (solver_presets_embedded.cpp, generated), so that a moved binary has them; the
// files stay the source and can be copied and passed with -options_file.
//
// Precedence: a preset only fills in what the user left unset. An option already in PETSc's
// database when the preset is applied (from the command line, PETSC_OPTIONS, an -options_file
// or .petscrc) keeps its value. Without -dipc_preset, "balanced" is applied.
#pragma once
#include <petscsys.h>

#include <string>
#include <vector>

namespace dipc {

struct SolverPreset {
  const char* name;
  const char* text;  // the options file, comments included
};

// The presets compiled into the program, in the order fast, balanced, accurate.
const std::vector<SolverPreset>& solver_presets();

// The preset applied when -dipc_preset is not given.
inline constexpr const char* kDefaultPreset = "balanced";

// The (name, value) pairs of an options file's text: '#' starts a comment, each line holds an
// option name (starting with '-') and optionally its value. Throws std::runtime_error naming
// the preset and line for anything else.
std::vector<std::pair<std::string, std::string>> preset_options(const SolverPreset& preset);

// Reads -dipc_preset (listed by -help with its choices; the value was checked by
// check_option_values) and sets each of the preset's options that the database does not hold
// yet. An option the user set in another form counts as set: -snes_lag_preconditioner replaces
// -dipc_pc_reuse (the two are refused together), -dipc_velocity_tol replaces
// -dipc_velocity_tol_rel. Returns the preset's name in *applied and the options it set in
// *inserted (so that tests can remove them again).
PetscErrorCode apply_solver_preset(MPI_Comm comm, std::string* applied, std::vector<std::string>* inserted);

}  // namespace dipc
