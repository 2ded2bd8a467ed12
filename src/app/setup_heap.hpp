// SetupHeap: while it lives, large arrays come from the heap and stay there for the next one,
// instead of each being mapped fresh from the kernel.
//
// glibc maps every allocation above its mmap threshold (at most 32 MB) anew and unmaps it on
// free. The partition and the setup allocate and free arrays of hundreds of MB in turn (at 1M
// hexes: face records, node maps, the Hessian pattern and its positions), so every page of
// every one of them faulted and was cleared again: a third of the setup's CPU samples were the
// kernel's (perf on a lent H200 host, docs/performance.md "Setup"). Served from the heap, a
// freed array's pages are reused as they are. The peak is the same: what the setup frees is
// kept, not more.
//
// Afterwards the thresholds are left where glibc's own adaptation takes them for large
// temporaries (mmap above 32 MB, trim above 64 MB), since setting any of them ends that
// adaptation. A no-op where the C library is not glibc.
#pragma once

namespace dipc {

class SetupHeap {
 public:
  SetupHeap();
  ~SetupHeap();
  SetupHeap(const SetupHeap&) = delete;
  SetupHeap& operator=(const SetupHeap&) = delete;
};

}  // namespace dipc
