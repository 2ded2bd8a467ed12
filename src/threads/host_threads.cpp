#include "threads/host_threads.hpp"

#include <algorithm>
#include <exception>
#include <stdexcept>
#include <string>
#include <vector>

#if defined(_OPENMP)
#include <omp.h>
#endif

namespace dipc {
namespace {
int threads_for_loops = 1;
std::size_t grain_cap = 0;
}  // namespace

int host_threads() { return threads_for_loops; }

bool host_threads_available() {
#if defined(_OPENMP)
  return true;
#else
  return false;
#endif
}

void set_host_threads(int threads, std::size_t grain_limit) {
  if (threads < 1) throw std::invalid_argument("set_host_threads: " + std::to_string(threads) + " threads");
  threads_for_loops = threads;
  grain_cap = grain_limit;
}

std::vector<std::size_t> chunk_starts(std::vector<std::size_t>& count, int chunks, std::size_t width) {
  std::vector<std::size_t> total(width, 0);
  for (int c = 0; c < chunks; ++c)
    for (std::size_t p = 0; p < width; ++p) {
      std::size_t& n = count[static_cast<std::size_t>(c) * width + p];
      const std::size_t items = n;
      n = total[p];
      total[p] += items;
    }
  return total;
}

int parallel_chunks(std::size_t n, const std::function<void(int, std::size_t, std::size_t)>& body, std::size_t grain) {
  if (grain_cap > 0) grain = std::min(grain, grain_cap);
  const std::size_t by_grain = std::max<std::size_t>(1, n / std::max<std::size_t>(1, grain));
  const int k = static_cast<int>(std::min<std::size_t>(static_cast<std::size_t>(threads_for_loops), by_grain));
  auto begin_of = [n, k](int c) {
    return static_cast<std::size_t>(split_point(0, static_cast<std::int64_t>(n), static_cast<std::size_t>(c),
                                                static_cast<std::size_t>(k)));
  };
  if (k == 1) {
    body(0, 0, n);
    return 1;
  }
  std::vector<std::exception_ptr> errors(static_cast<std::size_t>(k));
#if defined(_OPENMP)
  // num_threads: the OpenMP default of the process stays what app/openmp_threads.hpp set for
  // the solvers' libraries (one thread per rank unless OMP_NUM_THREADS says otherwise).
#pragma omp parallel for num_threads(k) schedule(static, 1)
#endif
  for (int c = 0; c < k; ++c) {
    try {
      body(c, begin_of(c), begin_of(c + 1));
    } catch (...) {
      errors[static_cast<std::size_t>(c)] = std::current_exception();
    }
  }
  for (const std::exception_ptr& e : errors)
    if (e) std::rethrow_exception(e);
  return k;
}

}  // namespace dipc
