// Checks of the -dipc_ options in PETSc's database, so that a bad value or a misspelt name
// stops the run with a message naming the option, instead of being ignored or ending in a
// PETSc error trace.
//
// Every -dipc_ option is declared once, with its kind and range, in the table of
// options/dipc_options.hpp; check_option_values tests the raw strings of those that are set
// before anything reads them (PETSc then parses values that are known to be valid). An option
// added later gets the same checks by adding its row there.
#pragma once
#include <petscsys.h>

#include <string>

#include "options/dipc_options.hpp"

namespace dipc {

// Why `value` is not acceptable for `spec` ("-dipc_steps -1: must be an integer >= 1"), or
// an empty string when it is. `value` is null when the option was given without one.
std::string option_value_problem(const OptionSpec& spec, const char* value);

// Throws std::runtime_error with option_value_problem's message for the first option of the
// table that is set to an unacceptable value. The same on every rank (PETSc gives every rank
// the same database).
void check_option_values();

// Throws std::runtime_error, the same on every rank of `comm`, when PETSc's database holds an
// option named -dipc_... that nothing has read: a misspelt or unknown option would otherwise
// be ignored. Call it once everything that reads options has run. The message suggests the
// closest option of the table when one is near.
void check_no_unknown_options(MPI_Comm comm);

// The option of the table whose name is closest to `name` (edit distance at most 3), or "".
std::string closest_option(const std::string& name);

}  // namespace dipc
