// Checks of the -dipc_ options in PETSc's database, so that a bad value or a misspelt name
// stops the run with a message naming the option, instead of being ignored or ending in a
// PETSc error trace.
//
// Every -dipc_ option is declared once in the table of option_checks.cpp with its kind and
// range; check_option_values tests the raw strings of those that are set before anything
// reads them (PETSc then parses values that are known to be valid). An option added later
// gets the same checks by adding its row there.
#pragma once
#include <petscsys.h>

#include <cmath>
#include <string>
#include <vector>

namespace dipc {

enum class OptionKind {
  flag,     // no value, or 1/0, true/false, yes/no, on/off (PETSc's booleans)
  integer,  // a decimal integer >= min that fits an int
  real,     // a finite number > min and < max
  text,     // a non-empty string
  choice,   // one of the words in `choices`
};

struct OptionSpec {
  const char* name;  // with the dash: "-dipc_steps"
  OptionKind kind;
  double min = 0;                 // integer: smallest value; real: values must exceed it
  const char* choices = nullptr;  // choice: words separated by spaces
  double max = HUGE_VAL;          // real: values must stay below it
};

// Every -dipc_ option that dipc reads, wherever it is read.
const std::vector<OptionSpec>& dipc_option_specs();

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
