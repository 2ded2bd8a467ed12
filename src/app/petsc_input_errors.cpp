#include "app/petsc_input_errors.hpp"

#include <petscsnes.h>

#include <cmath>
#include <stdexcept>
#include <vector>

namespace dipc {

namespace {

// PETSc calls the handler once where the error is raised (PETSC_ERROR_INITIAL) and once per
// PetscCall it passes on the way up (PETSC_ERROR_REPEAT), each time with the same code.
PetscErrorCode input_error_handler(MPI_Comm comm, int line, const char* function, const char* file, PetscErrorCode code,
                                   PetscErrorType type, const char* message, void* context) {
  if (code == PETSC_ERR_USER_INPUT) return code;
  return PetscTraceBackErrorHandler(comm, line, function, file, code, type, message, context);
}

// The value of `name` in the database; false when the option is not set.
bool option_value(const char* name, std::string* value) {
  char text[PETSC_MAX_PATH_LEN] = "";
  PetscBool set = PETSC_FALSE;
  if (PetscOptionsGetString(nullptr, nullptr, name, text, sizeof text, &set))
    throw std::runtime_error(std::string("cannot read ") + name);
  *value = text;
  return set;
}

// Runs a PETSc call with errors returned instead of printed, for values that PETSc's parsers
// refuse: true when the call succeeded.
template <class Call>
bool succeeds_quietly(Call call) {
  PetscPushErrorHandler(PetscReturnErrorHandler, nullptr);
  const PetscErrorCode error = call();
  PetscPopErrorHandler();
  return error == 0;
}

struct TypeOption {
  const char* name;
  const char* object;             // what the type is of, for the message
  const PetscFunctionList* list;  // the types registered with PETSc
};

std::string type_problem(const TypeOption& option) {
  std::string value;
  if (!option_value(option.name, &value)) return "";
  if (value.empty()) return std::string(option.name) + " needs a value";
  void (*create)(void) = nullptr;
  PetscFunctionListFind(*option.list, value.c_str(), &create);
  if (create) return "";
  return std::string(option.name) + " " + value + ": not a " + option.object + " type of this PETSc (-help lists them)";
}

// A tolerance: a number in [0, below), as KSPSetTolerances and SNESSetTolerances require.
std::string tolerance_problem(const char* name, double below) {
  std::string value;
  if (!option_value(name, &value)) return "";
  PetscReal v = 0;
  if (!succeeds_quietly([&] { return PetscOptionsGetReal(nullptr, nullptr, name, &v, nullptr); }))
    return std::string(name) + " " + value + ": not a number";
  if (v >= 0 && v < below) return "";
  return std::string(name) + " " + value + (std::isinf(below) ? ": must be >= 0" : ": must be in [0, 1)");
}

// An iteration limit: an integer >= 0 (PETSc's setters refuse a negative one only when they
// are next called, which for -ksp_max_it is in the middle of the first Newton iteration).
std::string iteration_limit_problem(const char* name) {
  std::string value;
  if (!option_value(name, &value)) return "";
  PetscInt v = 0;
  if (!succeeds_quietly([&] { return PetscOptionsGetInt(nullptr, nullptr, name, &v, nullptr); }))
    return std::string(name) + " " + value + ": not an integer PETSc can hold";
  return v >= 0 ? "" : std::string(name) + " " + value + ": must be an integer >= 0";
}

}  // namespace

void check_petsc_option_values() {
  // The type lists fill as the packages initialize, which otherwise happens as the first
  // solver objects are created.
  if (PCInitializePackage() || KSPInitializePackage() || SNESInitializePackage())
    throw std::runtime_error("cannot initialize PETSc's solvers");
  std::vector<std::string> problems;
  for (const TypeOption& option : {TypeOption{"-snes_type", "SNES", &SNESList},
                                   TypeOption{"-ksp_type", "KSP", &KSPList}, TypeOption{"-pc_type", "PC", &PCList},
                                   TypeOption{"-snes_linesearch_type", "SNES line search", &SNESLineSearchList}})
    problems.push_back(type_problem(option));
  for (const char* name : {"-ksp_rtol", "-snes_rtol"}) problems.push_back(tolerance_problem(name, 1));
  for (const char* name : {"-ksp_atol", "-snes_atol", "-snes_stol"})
    problems.push_back(tolerance_problem(name, HUGE_VAL));
  for (const char* name : {"-ksp_max_it", "-snes_max_it"}) problems.push_back(iteration_limit_problem(name));
  for (const std::string& problem : problems)
    if (!problem.empty()) throw std::runtime_error(problem);
}

PetscErrorCode push_input_error_handler() {
  PetscFunctionBeginUser;
  PetscCall(PetscPushErrorHandler(input_error_handler, nullptr));
  PetscFunctionReturn(0);
}

std::string last_petsc_error_message() {
  char* specific = nullptr;
  if (PetscErrorMessage(PETSC_ERR_USER_INPUT, nullptr, &specific) || !specific) return "bad input";
  return specific;
}

}  // namespace dipc
