// A cache of device blocks for a library that allocates and frees device temporaries at every
// call: hypre 2.32, built without a memory pool, calls cudaMalloc and cudaFree for the send
// buffers of every matrix-vector product across ranks (about 40 per V-cycle of BoomerAMG on two
// ranks, each cudaFree waiting for the whole device; counted with bench/cuda_call_census.c) and
// for the temporaries of every setup. Handed to hypre by app/hypre_device_memory.cpp.
//
// Freed blocks are kept by size class (four classes per power of two, so a block is at most 25 %
// larger than asked) and handed out again for the same class. Reuse needs no synchronisation
// where the library's kernels run in one stream, or in blocking streams, as hypre's do: work
// queued on a freed block finishes before work queued later on its next owner. Where cudaMalloc
// fails, the cached blocks go back to the driver and the allocation is tried once more.
//
// The cache holds at most kMaxCachedBytes, and never a block above kMaxCachedBlock: the blocks
// that recur at every call are small (a V-cycle's send buffers), while a setup's large
// temporaries differ in size from setup to setup and, kept, only add to the peak. Uncapped, the
// 3.4M-hex stack's device peak rose from 64 to 101 GB over 3 steps (docs/performance.md).
#pragma once
#include <cstddef>

namespace dipc::device::block_cache {

constexpr std::size_t kMaxCachedBytes = std::size_t{2} << 30;   // 2 GiB
constexpr std::size_t kMaxCachedBlock = std::size_t{64} << 20;  // 64 MiB

// A block of at least `bytes` (nullptr for 0 bytes, or where the device has no room even with
// the cache emptied).
void* allocate(std::size_t bytes) noexcept;
// Back into the cache, or to cudaFree where the cache is full, the block is above
// kMaxCachedBlock or the cache did not hand it out.
void release(void* p) noexcept;
// Gives every cached block back to the driver: for an allocation elsewhere that failed.
// Returns the bytes given back.
std::size_t empty() noexcept;

struct Stats {
  std::size_t reused = 0, allocated = 0;  // allocations served from the cache / by cudaMalloc
  std::size_t cached_bytes = 0;           // bytes held in the cache now
};
Stats stats();

}  // namespace dipc::device::block_cache
