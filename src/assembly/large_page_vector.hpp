// LargePageVector: a std::vector for the setup's largest arrays, whose memory is handed to the
// kernel as transparent-huge-page memory before it is first touched.
//
// The Hessian's pattern arrays (node-block maps, value positions, column indices, values) are
// hundreds of MB each at 1M hexes on a rank, and written once at setup. Where the kernel's THP
// mode is "madvise" (as Debian and Ubuntu ship it), that memory arrives in 4 KB pages, each a
// page fault and a zeroed page on first touch: on the lent H200 hosts that was about a fifth of
// the 1M-hex setup (docs/performance.md, "Setup"). With MADV_HUGEPAGE one fault maps 2 MB. The
// advice is only advice: a kernel in mode "never", or one out of huge pages, gives 4 KB pages as
// before. Arrays under 2 MB take the ordinary allocator.
#pragma once
#include <sys/mman.h>

#include <cstddef>
#include <cstdlib>
#include <new>
#include <vector>

namespace dipc {

template <class T>
struct LargePageAllocator {
  using value_type = T;
  static constexpr std::size_t kHugePage = std::size_t{2} << 20;

  LargePageAllocator() = default;
  template <class U>
  LargePageAllocator(const LargePageAllocator<U>&) noexcept {}

  T* allocate(std::size_t n) {
    const std::size_t bytes = n * sizeof(T);
    if (bytes < kHugePage) return static_cast<T*>(::operator new(bytes));
    const std::size_t rounded = (bytes + kHugePage - 1) / kHugePage * kHugePage;
    void* p = std::aligned_alloc(kHugePage, rounded);
    if (!p) throw std::bad_alloc();
    madvise(p, rounded, MADV_HUGEPAGE);  // ignored where it fails: 4 KB pages then
    return static_cast<T*>(p);
  }
  void deallocate(T* p, std::size_t n) noexcept {
    if (n * sizeof(T) < kHugePage)
      ::operator delete(p);
    else
      std::free(p);
  }
  friend bool operator==(const LargePageAllocator&, const LargePageAllocator&) { return true; }
  friend bool operator!=(const LargePageAllocator&, const LargePageAllocator&) { return false; }
};

template <class T>
using LargePageVector = std::vector<T, LargePageAllocator<T>>;

}  // namespace dipc
