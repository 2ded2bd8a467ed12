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

}  // namespace dipc
