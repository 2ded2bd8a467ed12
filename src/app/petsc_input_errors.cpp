#include "app/petsc_input_errors.hpp"

namespace dipc {

namespace {

// PETSc calls the handler once where the error is raised (PETSC_ERROR_INITIAL) and once per
// PetscCall it passes on the way up (PETSC_ERROR_REPEAT), each time with the same code.
PetscErrorCode input_error_handler(MPI_Comm comm, int line, const char* function, const char* file, PetscErrorCode code,
                                   PetscErrorType type, const char* message, void* context) {
  if (code == PETSC_ERR_USER_INPUT) return code;
  return PetscTraceBackErrorHandler(comm, line, function, file, code, type, message, context);
}

}  // namespace

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
