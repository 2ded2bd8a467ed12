#include "app/gpu_aware_mpi.hpp"

#include <petscdevice.h>

#include "app/hypre_functions.hpp"
#include "device/mpi_device_buffers.hpp"

namespace dipc {

namespace {

// hypre's HYPRE_SetGpuAwareMPI where the process has it (a hypre of 2.31 or later, loaded with
// PETSc) and PETSc has initialised hypre (hypre_functions.hpp).
bool tell_hypre(bool direct) {
  const auto set_gpu_aware_mpi = hypre_function<int (*)(int)>("HYPRE_SetGpuAwareMPI");
  if (!set_gpu_aware_mpi || !hypre_initialized()) return false;
  set_gpu_aware_mpi(direct ? 1 : 0);
  return true;
}

}  // namespace

PetscErrorCode settle_gpu_aware_mpi(MPI_Comm comm, bool device_backend, GpuAwareMpi* result) {
  PetscFunctionBeginUser;
  // PETSc's switch: -use_gpu_aware_mpi 0 keeps device buffers away from MPI, whatever MPI says.
  PetscBool allowed = PETSC_TRUE;
  PetscCall(PetscOptionsGetBool(nullptr, nullptr, "-use_gpu_aware_mpi", &allowed, nullptr));
  // A PETSc with CUDA that has initialised its device has sent a device buffer through MPI (and
  // would have stopped the run had that failed) unless the switch was off.
  const bool petsc_checked = PetscDeviceInitialized(PETSC_DEVICE_CUDA);
  const device::MpiCudaSupport mpi = device::query_mpi_cuda_support();
  int direct = device_backend && device::decide_device_direct(mpi, allowed, petsc_checked), all = 0;
  // All ranks or none: a device buffer sent to a rank that expects a host one would be misread.
  MPI_Allreduce(&direct, &all, 1, MPI_INT, MPI_MIN, comm);
  result->direct = all != 0;
  device::set_mpi_device_direct(result->direct);
  const bool hypre_told = tell_hypre(result->direct);
  if (!device_backend) {
    result->description.clear();
    PetscFunctionReturn(0);
  }
  const std::string says = std::string("MPI reports CUDA support: ") + device::to_string(mpi) +
                           (petsc_checked && allowed ? ", PETSc's device check passed" : "");
  if (result->direct)
    result->description = "CUDA-aware (" + says + "): PETSc, " + std::string(hypre_told ? "hypre " : "") +
                          "and dipc pass device buffers to MPI";
  else if (!allowed)
    result->description = "device buffers staged through the host (-use_gpu_aware_mpi 0; " + says + ")";
  else
    result->description = "device buffers staged through the host (" + says + ")";
  PetscFunctionReturn(0);
}

}  // namespace dipc
