#include "app/openmp_threads.hpp"

#include <sched.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <string>
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

// The cores this process may run on, as a byte mask of sizeof(cpu_set_t) bytes (no core when
// the system does not say, which gives one thread).
std::vector<unsigned char> affinity_mask() {
  cpu_set_t set;
  CPU_ZERO(&set);
  std::vector<unsigned char> mask(sizeof set, 0);
  if (sched_getaffinity(0, sizeof set, &set) != 0) return mask;
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

AffinityShare share_of_affinity(const std::vector<unsigned char>& mine,
                                const std::vector<std::vector<unsigned char>>& node_masks) {
  AffinityShare share;
  share.cores = count_cores(mine);
  for (const std::vector<unsigned char>& other : node_masks) {
    bool overlaps = false;
    for (std::size_t b = 0; b < std::min(mine.size(), other.size()); ++b) overlaps = overlaps || (mine[b] & other[b]);
    share.sharing += overlaps;
  }
  share.sharing = std::max(1, share.sharing);
  share.threads = std::max(1, share.cores / share.sharing);
  return share;
}

HostThreads choose_host_threads(MPI_Comm comm, int requested, const OpenMpThreads& openmp) {
  HostThreads result;
  // Every rank takes part in the node's exchange, whichever way it decides.
  MPI_Comm node;
  MPI_Comm_split_type(comm, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &node);
  int node_ranks = 1;
  MPI_Comm_size(node, &node_ranks);
  const std::vector<unsigned char> mine = affinity_mask();
  const int bytes = static_cast<int>(sizeof(cpu_set_t));
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
    std::vector<std::vector<unsigned char>> node_masks(static_cast<std::size_t>(node_ranks));
    for (int r = 0; r < node_ranks; ++r)
      node_masks[static_cast<std::size_t>(r)].assign(all.begin() + r * bytes, all.begin() + (r + 1) * bytes);
    const AffinityShare share = share_of_affinity(mine, node_masks);
    result.threads = share.threads;
    result.why = std::to_string(share.cores) + " cores / " + std::to_string(share.sharing) + " ranks";
    // mpirun binds 1 or 2 ranks to one core each by default: on a GPU node run with a rank per
    // GPU, the host work (new matrices, contact patterns) then runs on one core of many.
    std::vector<unsigned char> bound(mine.size(), 0);
    for (const std::vector<unsigned char>& other : node_masks)
      for (std::size_t b = 0; b < std::min(bound.size(), other.size()); ++b) bound[b] |= other[b];
    const long online = sysconf(_SC_NPROCESSORS_ONLN);
    if (online > 0 && count_cores(bound) < online)
      result.why += "; this node's ranks are bound to " + std::to_string(count_cores(bound)) + " of its " +
                    std::to_string(online) + " cores: mpirun --bind-to none or --map-by slot:PE=N gives them more";
  }
  set_host_threads(result.threads);
  return result;
}

}  // namespace dipc
