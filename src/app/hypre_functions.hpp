// hypre functions found by name at run time. dipc links no hypre of its own: PETSc loads one,
// of whatever version it was built with, or none; a function that older hypres lack (the GPU
// settings below) is looked up in the process instead of linked.
#pragma once
#include <dlfcn.h>

namespace dipc {

// The process's hypre function `name` as Fn, or nullptr where the loaded hypre (or none) lacks it.
template <class Fn>
Fn hypre_function(const char* name) {
  return reinterpret_cast<Fn>(dlsym(RTLD_DEFAULT, name));
}

// Whether PETSc has initialised the loaded hypre (HYPRE_Initialized; false without one): the
// GPU settings live in its handle, which exists only then, and a run whose solvers use no hypre
// leaves it alone.
inline bool hypre_initialized() {
  const auto initialized = hypre_function<int (*)()>("HYPRE_Initialized");
  return initialized && initialized() != 0;
}

}  // namespace dipc
