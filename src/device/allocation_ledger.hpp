// AllocationLedger: dipc's own live device allocations, summed by what they hold (the name that
// device::allocate takes, e.g. "node-block sources"), so that a run can say where its device
// memory goes: the run header gives the largest uses per element after the setup. Only dipc's
// own arrays pass through it; PETSc's vectors and matrix and hypre's hierarchy do not (they are
// the rest of the header's "setup used"). Host bookkeeping only; safe from several threads.
#pragma once
#include <cstddef>
#include <mutex>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

namespace dipc::device {

class AllocationLedger {
 public:
  // Allocation p of `bytes` holds `what` (a name that outlives the allocation: a literal).
  void add(const void* p, std::size_t bytes, const char* what);
  // p released; a pointer the ledger does not hold (null, or allocated elsewhere) is ignored.
  void remove(const void* p);

  struct Use {
    std::string what;
    std::size_t bytes = 0;
    std::size_t allocations = 0;
  };
  // The live allocations summed by name, largest first (ties by name).
  std::vector<Use> uses() const;
  std::size_t total_bytes() const;
  // "T B/element: the `most` largest uses in B/element, then the others together", all over
  // `elements` (at least 1), e.g. "2520 B/element: node-block sources 256, ..., 3 more 40".
  std::string per_element(std::size_t elements, std::size_t most) const;

 private:
  mutable std::mutex mutex_;
  std::unordered_map<const void*, std::pair<const char*, std::size_t>> live_;
};

// The process's ledger, which device::allocate and device::release keep.
AllocationLedger& allocation_ledger();

}  // namespace dipc::device
