// Host threads for the loops of the partition and the setup (issue 14: each GPU of the hosts
// dipc runs on comes with 16 or more cores, and the setup's host work ran on one of them).
//
// A loop over [0, n) is cut into contiguous chunks, one per thread: chunk c of k covers
// [n c / k, n (c + 1) / k). Callers write their results so that they do not depend on k (each
// item's own output, or per-chunk lists joined in chunk order), which the tests check by
// running the same input on 1 and on several threads. The count is set once by the program
// (app/openmp_threads.hpp); the libraries' default is 1, so that a test or a tool that does
// not ask runs as before.
#pragma once
#include <cstddef>
#include <cstdint>
#include <functional>
#include <utility>
#include <vector>

namespace dipc {

// Threads for the host loops below (>= 1). grain_limit > 0 caps every loop's grain (tests set
// 1, so that their small inputs take several chunks too); 0 keeps the loops' own.
int host_threads();
void set_host_threads(int threads, std::size_t grain_limit = 0);
// False where dipc was built without OpenMP: the chunks then run one after the other.
bool host_threads_available();

// Runs body(chunk, begin, end) for each of the k chunks of [0, n) and returns k: at most
// host_threads(), and fewer when chunks would hold less than `grain` items (a thread's start
// costs microseconds). Chunks run at once, each on its own thread. An exception thrown by a
// chunk is rethrown after every chunk has ended (that of the lowest chunk, when several throw).
int parallel_chunks(std::size_t n, const std::function<void(int chunk, std::size_t begin, std::size_t end)>& body,
                    std::size_t grain = 4096);

// Where part q of k of the range [begin, end) starts: the split parallel_chunks uses, for the
// loops in which each thread takes a range of keys (rows, nodes) and scans the items for its own.
inline std::int64_t split_point(std::int64_t begin, std::int64_t end, std::size_t q, std::size_t k) {
  return begin + (end - begin) * static_cast<std::int64_t>(q) / static_cast<std::int64_t>(k);
}

// Per-chunk counts to per-chunk starts: count[c * width + p], chunk c's items for list p
// (c < chunks), becomes where chunk c's items start in list p, after the lower chunks' (the
// place one pass in order would put them). Returns each list's total.
std::vector<std::size_t> chunk_starts(std::vector<std::size_t>& count, int chunks, std::size_t width = 1);

// parallel_chunks for a body that does not need its chunk's index.
inline void parallel_for(std::size_t n, const std::function<void(std::size_t begin, std::size_t end)>& body,
                         std::size_t grain = 4096) {
  parallel_chunks(
      n, [&body](int, std::size_t begin, std::size_t end) { body(begin, end); }, grain);
}

// The items that body(begin, end, out) appends to `out` for the chunks of [0, n), joined in
// chunk order: the list one pass over [0, n) in order gives, for any number of threads.
template <class T, class Body>
std::vector<T> parallel_collect(std::size_t n, Body body, std::size_t grain = 4096) {
  std::vector<std::vector<T>> parts(static_cast<std::size_t>(host_threads()));
  const int chunks = parallel_chunks(
      n, [&](int c, std::size_t begin, std::size_t end) { body(begin, end, parts[static_cast<std::size_t>(c)]); },
      grain);
  if (chunks == 1) return std::move(parts[0]);
  std::size_t total = 0;
  for (int c = 0; c < chunks; ++c) total += parts[static_cast<std::size_t>(c)].size();
  std::vector<T> all;
  all.reserve(total);
  for (int c = 0; c < chunks; ++c) {
    const std::vector<T>& part = parts[static_cast<std::size_t>(c)];
    all.insert(all.end(), part.begin(), part.end());
  }
  return all;
}

// `value` += `add` atomically (relaxed order: a count or a slot whose final value, not the
// order of the additions, is what the caller uses). Returns the value before the addition.
template <class T>
T atomic_fetch_add(T& value, T add) {
  return __atomic_fetch_add(&value, add, __ATOMIC_RELAXED);
}

}  // namespace dipc
