#include "app/openmp_threads.hpp"

#include <cstdlib>

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

}  // namespace dipc
