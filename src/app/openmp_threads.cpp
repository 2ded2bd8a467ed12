#include "app/openmp_threads.hpp"

#include <sched.h>

#include <algorithm>
#include <cstdlib>
#include <vector>

#include "threads/host_threads.hpp"

#if defined(_OPENMP)
#include <omp.h>
#endif

namespace dipc {

OpenMpThreads limit_openmp_threads() {
  OpenMpThreads result;
#if defined(_OPENMP)
  const char* environment = std::getenv("OMP_NUM_THREADS");
  result.from_environment = environment != nullptr && environment[0] != '\0';
  // omp_set_num_threads sets the calling thread's default for later parallel regions: the one
  // libgomp read from the environment at start-up is replaced only where none was given.
  if (!result.from_environment) omp_set_num_threads(1);
  result.threads = omp_get_max_threads();
#else
  result.available = false;
  result.threads = 0;
#endif
  return result;
}

namespace {

// The cores this process may run on, as a byte mask (empty when the system does not say).
std::vector<unsigned char> affinity_mask() {
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof set, &set) != 0) return {};
  std::vector<unsigned char> mask(sizeof set, 0);
  for (int cpu = 0; cpu < CPU_SETSIZE; ++cpu)
    if (CPU_ISSET(cpu, &set)) mask[static_cast<std::size_t>(cpu / 8)] |= static_cast<unsigned char>(1u << (cpu % 8));
  return mask;
}

int count_cores(const std::vector<unsigned char>& mask) {
  int n = 0;
  for (unsigned char byte : mask) n += __builtin_popcount(byte);
  return n;
}

}  // namespace

HostThreads choose_host_threads(MPI_Comm comm, int requested, const OpenMpThreads& openmp) {
  HostThreads result;
  // Every rank takes part in the node's exchange, whichever way it decides.
  MPI_Comm node;
  MPI_Comm_split_type(comm, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &node);
  int node_ranks = 1;
  MPI_Comm_size(node, &node_ranks);
  std::vector<unsigned char> mine = affinity_mask();
  const int bytes = static_cast<int>(sizeof(cpu_set_t));
  if (mine.empty()) mine.assign(static_cast<std::size_t>(bytes), 0);
  std::vector<unsigned char> all(static_cast<std::size_t>(bytes) * static_cast<std::size_t>(node_ranks));
  MPI_Allgather(mine.data(), bytes, MPI_UNSIGNED_CHAR, all.data(), bytes, MPI_UNSIGNED_CHAR, node);
  MPI_Comm_free(&node);
  if (!host_threads_available()) {
    result.why = "built without OpenMP";
  } else if (requested > 0) {
    result.threads = requested;
    result.why = "-dipc_host_threads";
  } else if (openmp.from_environment) {
    result.threads = openmp.threads;
    result.why = "OMP_NUM_THREADS";
  } else {
    int sharing = 0;  // ranks of this node (this one included) that may run on a core of this rank's
    for (int r = 0; r < node_ranks; ++r) {
      bool overlaps = false;
      for (int b = 0; b < bytes; ++b) overlaps = overlaps || (all[static_cast<std::size_t>(r * bytes + b)] & mine[b]);
      sharing += overlaps;
    }
    const int cores = count_cores(mine);
    result.threads = std::max(1, cores / std::max(1, sharing));
    result.why = std::to_string(cores) + " cores / " + std::to_string(std::max(1, sharing)) + " ranks";
  }
  set_host_threads(result.threads);
  return result;
}

}  // namespace dipc
