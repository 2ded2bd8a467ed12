// OpenMP threads per MPI rank. dipc runs one MPI rank per core (per GPU on GPU nodes), but
// Debian's hypre and SuperLU_DIST are built with OpenMP: with OMP_NUM_THREADS unset, every
// rank's BoomerAMG opens one thread per core of the node, so R ranks on C cores run R·C threads
// that contend for the same cores (and libgomp's idle threads spin for a while after each
// parallel region, taking cycles from the neighbouring ranks' element loops too). dipc therefore
// runs one thread per rank unless OMP_NUM_THREADS says otherwise (docs/performance.md, "CPU
// strong scaling").
//
// The partition's and the setup's own loops (threads/host_threads.hpp) take their threads
// separately: as many as the cores this rank may run on, shared with the other ranks of the node
// that may run on them too, since nothing else runs during the setup.
#pragma once
#include <mpi.h>

#include <string>
#include <vector>

namespace dipc {

struct OpenMpThreads {
  int threads = 1;                // per rank for the OpenMP regions that follow (hypre's)
  bool from_environment = false;  // OMP_NUM_THREADS was set and is honoured
  bool available = true;          // false: dipc was built without OpenMP (the libraries' default stays)
};

// Call before the first solve, on every rank (it acts on the calling thread, which runs the
// solvers). Sets one thread per rank where OMP_NUM_THREADS is unset or empty.
OpenMpThreads limit_openmp_threads();

struct HostThreads {
  int threads = 1;
  std::string why;  // for the run header: "-dipc_host_threads", "OMP_NUM_THREADS" or the cores and ranks
};

// The automatic count: the cores of this rank's affinity mask `mine` (a byte per 8 CPUs),
// divided by the node's ranks whose masks (`node_masks`, this rank's included) overlap it, at
// least 1.
struct AffinityShare {
  int cores = 0, sharing = 0, threads = 1;
};
AffinityShare share_of_affinity(const std::vector<unsigned char>& mine,
                                const std::vector<std::vector<unsigned char>>& node_masks);

// The threads of the host loops on this rank, and set_host_threads with them: `requested` (from
// -dipc_host_threads) when > 0; else OMP_NUM_THREADS where set; else the cores of this rank's
// CPU affinity divided by the ranks of this node whose affinity overlaps it (at least 1: a rank
// bound to one core, as mpirun binds 1 or 2 ranks, gets one thread). Collective on comm.
HostThreads choose_host_threads(MPI_Comm comm, int requested, const OpenMpThreads& openmp);

}  // namespace dipc
