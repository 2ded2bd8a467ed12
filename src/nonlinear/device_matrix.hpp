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

}  // namespace dipc
