// The run's answer to "does MPI take device pointers?" (device/mpi_device_buffers.hpp): asked of
// MPI and PETSc, agreed by every rank, told to hypre, and described for the run header (issue 30).
#pragma once
#include <mpi.h>
#include <petscsys.h>

#include <string>

namespace dipc {

struct GpuAwareMpi {
  bool direct = false;      // device buffers go to MPI as they are (PETSc, hypre and dipc's own)
  std::string description;  // for the run header
};

// Collective; after the integrator's setup, so that PETSc has initialised (and checked) the
// device where it uses one. device_backend: dipc's data lives on a GPU. Sets
// device::set_mpi_device_direct and, where the run's hypre has HYPRE_SetGpuAwareMPI (2.31 and
// later, found at run time), tells hypre the same: PETSc 3.22 does not, and hypre otherwise
// keeps the default it was built with.
PetscErrorCode settle_gpu_aware_mpi(MPI_Comm comm, bool device_backend, GpuAwareMpi* result);

}  // namespace dipc
