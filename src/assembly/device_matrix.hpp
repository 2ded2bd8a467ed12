// Where the Hessian matrix keeps its values: host or device memory. A device matrix is a
// CUSPARSE one, or MATHYPRE where PETSc's hypre runs on the GPU (its ParCSR arrays then live
// on the device, PETSC_HAVE_HYPRE_DEVICE); Debian's PETSc has neither, so there both answers
// are false for every matrix type.
#pragma once
#include <petscmat.h>

namespace dipc {

// True when the options database asks for a device matrix with -mat_type: a CUSPARSE matrix,
// or MATHYPRE where PETSc's hypre runs on the GPU (its ParCSR arrays then live on the
// device). Assembly, the Hessian values and BoomerAMG then stay on the GPU.
bool device_matrix_requested();
// The same for a matrix that exists: whether its values live in device memory, so that
// MatSetValuesCOO should be given device values.
bool matrix_on_device(Mat J);

// With a PETSc whose hypre runs only on the GPU (PETSC_HAVE_HYPRE_DEVICE and CUDA, such as
// a PETSc 3.22 configured --with-cuda --download-hypre), BoomerAMG cannot take host vectors: KSP stops in PCApply with "HYPRE_MEMORY_
// DEVICE expects a device vector". So where BoomerAMG is the preconditioner (-pc_type unset or
// hypre) and neither -vec_type nor -mat_type is given, this sets -vec_type cuda -mat_type hypre.
// Call before any Vec or Mat is created; a no-op with Debian's PETSc. Sets *changed when it did.
PetscErrorCode default_types_for_device_hypre(PetscBool* changed);

}  // namespace dipc
