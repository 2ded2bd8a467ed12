// block_cache.hpp on the CUDA runtime.
#include <cuda_runtime.h>

#include <map>
#include <mutex>
#include <unordered_map>
#include <vector>

#include "device/block_cache.hpp"

namespace dipc::device::block_cache {

namespace {

struct Cache {
  std::mutex mutex;
  std::unordered_map<void*, std::size_t> class_of;     // every block handed out or cached
  std::map<std::size_t, std::vector<void*>> free_by_class;
  Stats stats;
};

Cache& cache() {
  // Never destroyed: the library may free blocks while the process exits.
  static Cache* c = new Cache;
  return *c;
}

// The size class of a request: multiples of 256 bytes up to 1 KiB, then four classes per power
// of two.
std::size_t size_class(std::size_t bytes) {
  if (bytes <= 1024) return (bytes + 255) & ~std::size_t{255};
  const int top = 63 - __builtin_clzll(bytes);
  const std::size_t step = std::size_t{1} << (top - 2);
  return (bytes + step - 1) & ~(step - 1);
}

// Gives every cached block back to the driver (the caller holds the lock); the bytes freed.
std::size_t empty_locked(Cache& c) {
  const std::size_t bytes = c.stats.cached_bytes;
  for (auto& [size, blocks] : c.free_by_class)
    for (void* p : blocks) {
      cudaFree(p);
      c.class_of.erase(p);
    }
  c.free_by_class.clear();
  c.stats.cached_bytes = 0;
  return bytes;
}

}  // namespace

void* allocate(std::size_t bytes) noexcept {
  if (bytes == 0) return nullptr;
  Cache& c = cache();
  const std::size_t size = size_class(bytes);
  std::lock_guard<std::mutex> lock(c.mutex);
  auto it = c.free_by_class.find(size);
  if (it != c.free_by_class.end() && !it->second.empty()) {
    void* p = it->second.back();
    it->second.pop_back();
    c.stats.cached_bytes -= size;
    ++c.stats.reused;
    return p;
  }
  void* p = nullptr;
  if (cudaMalloc(&p, size) != cudaSuccess) {
    cudaGetLastError();
    empty_locked(c);
    if (cudaMalloc(&p, size) != cudaSuccess) {
      cudaGetLastError();
      return nullptr;
    }
  }
  c.class_of.emplace(p, size);
  ++c.stats.allocated;
  return p;
}

void release(void* p) noexcept {
  if (!p) return;
  Cache& c = cache();
  std::lock_guard<std::mutex> lock(c.mutex);
  const auto it = c.class_of.find(p);
  if (it == c.class_of.end()) {
    cudaFree(p);
    return;
  }
  const std::size_t size = it->second;
  if (size > kMaxCachedBlock || c.stats.cached_bytes + size > kMaxCachedBytes) {
    c.class_of.erase(it);
    cudaFree(p);
    return;
  }
  c.free_by_class[size].push_back(p);
  c.stats.cached_bytes += size;
}

std::size_t empty() noexcept {
  Cache& c = cache();
  std::lock_guard<std::mutex> lock(c.mutex);
  return empty_locked(c);
}

Stats stats() {
  Cache& c = cache();
  std::lock_guard<std::mutex> lock(c.mutex);
  return c.stats;
}

}  // namespace dipc::device::block_cache
