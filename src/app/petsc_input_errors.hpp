// Bad input found inside PETSc-style code (functions that return a PetscErrorCode) is raised
// there as a PETSc error with the code PETSC_ERR_USER_INPUT (PetscCheck/SETERRQ), not thrown:
// a C++ exception would unwind through PETSc's call stack. The program reports such an error
// like a thrown input error, "dipc: error: <message>" with exit status 1, without PETSc's
// traceback, which stays for every other PETSc error (defects).
#pragma once
#include <petscsys.h>

#include <string>

namespace dipc {

// Pushes an error handler that is silent for PETSC_ERR_USER_INPUT and prints PETSc's traceback
// for every other error. Call after PetscInitialize.
PetscErrorCode push_input_error_handler();

// The message of the last PETSc error raised on this rank (PetscErrorMessage's text).
std::string last_petsc_error_message();

// Checks the values of PETSc's own solver options that users give most (-snes_type, -ksp_type,
// -pc_type, -snes_linesearch_type, the -ksp_ and -snes_ tolerances and iteration limits), with
// PETSc's parsers and the ranges PETSc's setters check, before the solvers read them: there a
// bad value ends in a traceback and MPI_Abort, in the setup or, for -ksp_max_it, in the first
// Newton iteration. Throws std::runtime_error "<option> <value>: <what>", the same on every rank
// (PETSc gives every rank the same database). Options under a prefix are left to PETSc.
void check_petsc_option_values();

}  // namespace dipc
