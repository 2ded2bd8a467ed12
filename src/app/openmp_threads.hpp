// OpenMP threads per MPI rank. dipc runs one MPI rank per core (per GPU on GPU nodes), but
// Debian's hypre and SuperLU_DIST are built with OpenMP: with OMP_NUM_THREADS unset, every
// rank's BoomerAMG opens one thread per core of the node, so R ranks on C cores run R·C threads
// that contend for the same cores (and libgomp's idle threads spin for a while after each
// parallel region, taking cycles from the neighbouring ranks' element loops too). dipc therefore
// runs one thread per rank unless OMP_NUM_THREADS says otherwise (docs/performance.md, "CPU
// strong scaling").
#pragma once

namespace dipc {

struct OpenMpThreads {
  int threads = 1;              // per rank for the OpenMP regions that follow (hypre's)
  bool from_environment = false;  // OMP_NUM_THREADS was set and is honoured
  bool available = true;        // false: dipc was built without OpenMP (the libraries' default stays)
};

// Call before the first solve, on every rank (it acts on the calling thread, which runs the
// solvers). Sets one thread per rank where OMP_NUM_THREADS is unset or empty.
OpenMpThreads limit_openmp_threads();

}  // namespace dipc
