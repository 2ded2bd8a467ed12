// The run options as the program takes them, shared by `dipc` (main.cpp) and the Python
// module: every value checked before anything reads it, the solver preset applied, the -dipc_
// options read, the scene's size checked against the ranks.
#pragma once
#include <petscsys.h>

#include "app/run_options.hpp"
#include "io/scene.hpp"

namespace dipc {

// Collective over comm; reads the current default options database. Input errors throw
// std::runtime_error with the same message on every rank.
PetscErrorCode checked_run_options(MPI_Comm comm, const Scene& scene, RunOptions* options);

}  // namespace dipc
