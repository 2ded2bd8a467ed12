// parallel_chunks: contiguous chunks that cover [0, n) in order, as many as the threads and the
// grain allow, run at once; an exception of a chunk comes back to the caller after all chunks;
// per-chunk counts become the starts one pass in order gives.
#include <gtest/gtest.h>

#include <stdexcept>
#include <vector>

#include "threads/host_threads.hpp"

namespace dipc {
namespace {

// The thread count of a test, restored afterwards (other tests expect the default, 1).
struct Threads {
  explicit Threads(int n) { set_host_threads(n); }
  ~Threads() { set_host_threads(1); }
};

TEST(HostThreads, ChunksCoverTheRangeInOrder) {
  for (int threads : {1, 2, 3, 7}) {
    Threads use(threads);
    for (std::size_t n : {0, 1, 5, 4096, 10000, 100003}) {
      std::vector<std::size_t> begin(threads, 0), end(threads, 0);
      std::vector<int> hits(n, 0);
      const int k = parallel_chunks(
          n,
          [&](int c, std::size_t b, std::size_t e) {
            begin[c] = b, end[c] = e;
            for (std::size_t i = b; i < e; ++i) ++hits[i];
          },
          1000);
      const std::size_t by_grain = std::max<std::size_t>(1, n / 1000);
      EXPECT_EQ(static_cast<std::size_t>(k), std::min<std::size_t>(threads, by_grain)) << n;
      EXPECT_EQ(begin[0], 0u);
      EXPECT_EQ(end[k - 1], n);
      for (int c = 1; c < k; ++c) EXPECT_EQ(begin[c], end[c - 1]);
      for (int h : hits) ASSERT_EQ(h, 1);
    }
  }
}

TEST(HostThreads, ChunksRunAtOnce) {
  // Every chunk waits until all have started: this ends only if they run on threads of their own.
  if (!host_threads_available()) GTEST_SKIP() << "built without OpenMP: chunks run one after the other";
  Threads use(4);
  int started = 0;
  const int k = parallel_chunks(
      4,
      [&](int, std::size_t, std::size_t) {
        atomic_fetch_add(started, 1);
        while (__atomic_load_n(&started, __ATOMIC_RELAXED) < 4) {
        }
      },
      1);
  EXPECT_EQ(k, 4);
}

TEST(HostThreads, LowestChunksExceptionIsRethrown) {
  Threads use(4);
  try {
    parallel_chunks(
        4000,
        [](int c, std::size_t, std::size_t) {
          if (c >= 1) throw std::runtime_error("chunk " + std::to_string(c));
        },
        1);
    FAIL() << "expected the chunks' exception";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "chunk 1");
  }
}

TEST(HostThreads, ChunkStartsFollowTheLowerChunks) {
  // 3 chunks, 2 lists: chunk c's count for list p at [c * 2 + p].
  std::vector<std::size_t> count{2, 0, 1, 5, 3, 1};
  const std::vector<std::size_t> total = chunk_starts(count, 3, 2);
  EXPECT_EQ(total, (std::vector<std::size_t>{6, 6}));
  EXPECT_EQ(count, (std::vector<std::size_t>{0, 0, 2, 0, 3, 5}));
  std::vector<std::size_t> one{4, 0, 7, 9};  // only the first 3 are chunks
  EXPECT_EQ(chunk_starts(one, 3)[0], 11u);
  EXPECT_EQ(one, (std::vector<std::size_t>{0, 4, 4, 9}));
}

TEST(HostThreads, ZeroThreadsAreRefused) { EXPECT_THROW(set_host_threads(0), std::invalid_argument); }

}  // namespace
}  // namespace dipc
