// The cache of device blocks handed to hypre (device/block_cache.hpp): a freed block comes back
// for a request of its size class, blocks above kMaxCachedBlock and beyond kMaxCachedBytes go
// back to the driver, and empty() returns what the cache held.
#include <gtest/gtest.h>

#include <vector>

#include "device/block_cache.hpp"
#include "device/device_runtime.hpp"

namespace dipc::device {
namespace {

TEST(BlockCache, ReusesAFreedBlockOfTheSameClass) {
  if (device_count() == 0) GTEST_SKIP() << "no CUDA device";
  block_cache::empty();
  void* a = block_cache::allocate(100000);
  ASSERT_NE(a, nullptr);
  block_cache::release(a);
  const block_cache::Stats before = block_cache::stats();
  EXPECT_GT(before.cached_bytes, 0u);
  // 100000 and 101000 bytes fall in one class (four per power of two).
  void* b = block_cache::allocate(101000);
  EXPECT_EQ(b, a);
  EXPECT_EQ(block_cache::stats().reused, before.reused + 1);
  EXPECT_EQ(block_cache::stats().cached_bytes, 0u);
  block_cache::release(b);
  EXPECT_EQ(block_cache::empty(), before.cached_bytes);
  EXPECT_EQ(block_cache::stats().cached_bytes, 0u);
  EXPECT_EQ(block_cache::allocate(0), nullptr);
}

TEST(BlockCache, KeepsNoLargeBlockAndNoMoreThanItsCap) {
  if (device_count() == 0) GTEST_SKIP() << "no CUDA device";
  block_cache::empty();
  void* large = block_cache::allocate(block_cache::kMaxCachedBlock + 1);
  ASSERT_NE(large, nullptr);
  block_cache::release(large);
  EXPECT_EQ(block_cache::stats().cached_bytes, 0u);

  // Blocks of the largest cached size, more of them than the cap holds.
  const std::size_t n = block_cache::kMaxCachedBytes / block_cache::kMaxCachedBlock + 2;
  std::vector<void*> blocks;
  for (std::size_t k = 0; k < n; ++k) {
    blocks.push_back(block_cache::allocate(block_cache::kMaxCachedBlock));
    ASSERT_NE(blocks.back(), nullptr);
  }
  for (void* p : blocks) block_cache::release(p);
  EXPECT_LE(block_cache::stats().cached_bytes, block_cache::kMaxCachedBytes);
  EXPECT_GT(block_cache::stats().cached_bytes, 0u);
  EXPECT_LE(block_cache::empty(), block_cache::kMaxCachedBytes);
}

}  // namespace
}  // namespace dipc::device
