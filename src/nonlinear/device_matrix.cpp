#include "nonlinear/device_matrix.hpp"

#include <cstring>

namespace dipc {

bool device_matrix_requested() {
  char type[64] = "";
  PetscBool set = PETSC_FALSE;
  PetscOptionsGetString(nullptr, nullptr, "-mat_type", type, sizeof type, &set);
  if (!set) return false;
  return std::strstr(type, "cusparse") != nullptr || (PetscDefined(HAVE_HYPRE_DEVICE) && !std::strcmp(type, MATHYPRE));
}

bool matrix_on_device(Mat J) {
  PetscBool cusparse = PETSC_FALSE, hypre = PETSC_FALSE;
  PetscObjectTypeCompareAny(reinterpret_cast<PetscObject>(J), &cusparse, MATAIJCUSPARSE, MATSEQAIJCUSPARSE,
                            MATMPIAIJCUSPARSE, "");
  PetscObjectTypeCompare(reinterpret_cast<PetscObject>(J), MATHYPRE, &hypre);
  return cusparse || (PetscDefined(HAVE_HYPRE_DEVICE) && hypre);
}

}  // namespace dipc
