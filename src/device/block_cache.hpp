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
#pragma once
#include <cstddef>

namespace dipc::device::block_cache {

// A block of at least `bytes` (nullptr for 0 bytes, or where the device has no room even with
// the cache emptied).
void* allocate(std::size_t bytes) noexcept;
// Back into the cache; a pointer the cache did not hand out is given to cudaFree.
void release(void* p) noexcept;

struct Stats {
  std::size_t reused = 0, allocated = 0;  // allocations served from the cache / by cudaMalloc
  std::size_t cached_bytes = 0;           // bytes held in the cache now
};
Stats stats();

}  // namespace dipc::device::block_cache
