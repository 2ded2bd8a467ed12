#include "assembly/device_matrix.hpp"

#include <petscpc.h>

#include <cstring>

namespace dipc {

// These two answer a bool, so a failing PETSc call aborts (PetscCallAbort) rather than being
// ignored: an option or type query fails only on a defect (a corrupt object or database).
bool device_matrix_requested() {
  char type[64] = "";
  PetscBool set = PETSC_FALSE;
  PetscCallAbort(PETSC_COMM_SELF, PetscOptionsGetString(nullptr, nullptr, "-mat_type", type, sizeof type, &set));
  if (!set) return false;
  return std::strstr(type, "cusparse") != nullptr || (PetscDefined(HAVE_HYPRE_DEVICE) && !std::strcmp(type, MATHYPRE));
}

bool matrix_on_device(Mat J) {
  PetscBool cusparse = PETSC_FALSE, hypre = PETSC_FALSE;
  const PetscObject object = reinterpret_cast<PetscObject>(J);
  PetscCallAbort(PetscObjectComm(object), PetscObjectTypeCompareAny(object, &cusparse, MATAIJCUSPARSE,
                                                                    MATSEQAIJCUSPARSE, MATMPIAIJCUSPARSE, ""));
  PetscCallAbort(PetscObjectComm(object), PetscObjectTypeCompare(object, MATHYPRE, &hypre));
  return cusparse || (PetscDefined(HAVE_HYPRE_DEVICE) && hypre);
}

PetscErrorCode default_types_for_device_hypre(PetscBool* changed) {
  PetscFunctionBeginUser;
  *changed = PETSC_FALSE;
  if (!(PetscDefined(HAVE_HYPRE_DEVICE) && PetscDefined(HAVE_CUDA))) PetscFunctionReturn(0);
  char pc[64] = "";
  PetscBool pc_set, vec_set, mat_set;
  PetscCall(PetscOptionsGetString(nullptr, nullptr, "-pc_type", pc, sizeof pc, &pc_set));
  PetscCall(PetscOptionsHasName(nullptr, nullptr, "-vec_type", &vec_set));
  PetscCall(PetscOptionsHasName(nullptr, nullptr, "-mat_type", &mat_set));
  if ((pc_set && std::strcmp(pc, PCHYPRE) != 0) || vec_set || mat_set) PetscFunctionReturn(0);
  PetscCall(PetscOptionsSetValue(nullptr, "-vec_type", "cuda"));
  PetscCall(PetscOptionsSetValue(nullptr, "-mat_type", MATHYPRE));
  *changed = PETSC_TRUE;
  PetscFunctionReturn(0);
}

}  // namespace dipc
