// hypre's device temporaries from dipc's cache of device blocks (device/block_cache.hpp) instead
// of a cudaMalloc and a cudaFree each, where BoomerAMG runs on the GPU and the run's hypre has the
// hooks for it (hypre_SetUserDeviceMalloc / hypre_SetUserDeviceMfree, found at run time).
// -dipc_hypre_block_cache 0 leaves hypre as it was built.
#pragma once
#include <mpi.h>
#include <petscsys.h>

#include <string>

namespace dipc {

// Reads -dipc_hypre_block_cache (default on). After the integrator's setup, when PETSc has
// initialised hypre (its device matrix exists); hypre's blocks from before go back to cudaFree.
// device_backend: dipc's data lives on a GPU. *description: for the run header ("" where nothing
// was changed). Once given, the hooks stay for the process's lifetime: blocks handed out must
// come back to the cache.
PetscErrorCode use_block_cache_for_hypre(MPI_Comm comm, bool device_backend, std::string* description);

}  // namespace dipc
