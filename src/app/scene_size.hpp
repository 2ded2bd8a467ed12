// A scene too large for the machine is refused before anything is allocated: a box's element
// count (its resolution times -dipc_refine) was multiplied out in int and then allocated, which
// ended in std::bad_alloc or an overflow, naming neither the key nor the option.
#pragma once
#include <mpi.h>

#include "io/scene.hpp"

namespace dipc {

// Throws std::runtime_error, the same on every rank of `comm`, when a box body's resolution times
// `refine` exceeds an int along an axis or 64-bit ids in all, or when the scene's generated
// elements need more memory than all the nodes of `comm` have available (MemAvailable).
void check_scene_size(const Scene& scene, int refine, MPI_Comm comm);

}  // namespace dipc
