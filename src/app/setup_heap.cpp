#include "app/setup_heap.hpp"

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace dipc {

#if defined(__GLIBC__)
SetupHeap::SetupHeap() {
  // No mmapped chunks (every allocation from the heap, which grows with brk) and no trimming
  // of the heap's top while the setup runs. Threads other than the main one keep their own
  // arenas; the setup allocates its arrays on the main thread.
  mallopt(M_MMAP_MAX, 0);
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
}

SetupHeap::~SetupHeap() {
  mallopt(M_MMAP_MAX, 65536);                   // glibc's default count
  mallopt(M_MMAP_THRESHOLD, 32 * 1024 * 1024);  // the most its adaptation reaches on 64-bit
  mallopt(M_TRIM_THRESHOLD, 64 * 1024 * 1024);  // twice that, as the adaptation sets it
}
#else
SetupHeap::SetupHeap() = default;
SetupHeap::~SetupHeap() = default;
#endif

}  // namespace dipc
