#include "app/hypre_device_memory.hpp"

#include "app/hypre_functions.hpp"
#include "device/block_cache.hpp"
#include "options/dipc_options.hpp"

namespace dipc {

#if PetscDefined(HAVE_HYPRE_DEVICE)
namespace {

void cached_malloc(void** p, std::size_t bytes) { *p = device::block_cache::allocate(bytes); }
void cached_free(void* p) { device::block_cache::release(p); }

bool hooks_given = false;

}  // namespace
#endif

PetscErrorCode use_block_cache_for_hypre(MPI_Comm comm, bool device_backend, std::string* description) {
  PetscFunctionBeginUser;
  description->clear();
  constexpr const OptionSpec& option = dipc_option("-dipc_hypre_block_cache");
  PetscBool wanted = PETSC_TRUE;
  PetscOptionsBegin(comm, nullptr, "dipc hypre device memory", "HypreDeviceMemory");
  PetscCall(PetscOptionsBool(option.name, option.help, option.manual, wanted, &wanted, nullptr));
  PetscOptionsEnd();
#if PetscDefined(HAVE_HYPRE_DEVICE)
  if (!device_backend) PetscFunctionReturn(0);
  if (!wanted) {
    *description = hooks_given ? "hypre device temporaries: dipc's block cache (given earlier in this process)"
                               : "hypre device temporaries: cudaMalloc and cudaFree (-dipc_hypre_block_cache 0)";
    PetscFunctionReturn(0);
  }
  using MallocFunc = void (*)(void**, std::size_t);
  using FreeFunc = void (*)(void*);
  const auto set_malloc = hypre_function<int (*)(MallocFunc)>("hypre_SetUserDeviceMalloc");
  const auto set_free = hypre_function<int (*)(FreeFunc)>("hypre_SetUserDeviceMfree");
  if (!set_malloc || !set_free) {
    *description = "hypre device temporaries: cudaMalloc and cudaFree (this hypre has no allocator hooks)";
    PetscFunctionReturn(0);
  }
  // Only a hypre that PETSc has initialised (its solvers use it): hypre's hooks live in its handle.
  if (!hypre_initialized()) PetscFunctionReturn(0);
  set_malloc(cached_malloc);
  set_free(cached_free);
  hooks_given = true;
  *description = "hypre device temporaries: dipc's block cache (-dipc_hypre_block_cache 0: cudaMalloc each)";
#else
  (void)device_backend;
#endif
  PetscFunctionReturn(0);
}

}  // namespace dipc
