// TargetPart: a part of the Hessian's raw values (the terms whose pattern changes: contact,
// friction) mapped value by value onto the matrix's entries, without a reduction of its own.
//
// A CooPart first sums its raw values per distinct (row, col) and needs a sort of its COO list
// for that (CooReduction): O(n log n) on the host, 144 entries per contact pair, 1.5-9 s per
// active-set change on contact-rich scenes at 1M hexes on one H200's host. Here each raw value
// just looks up its matrix entry (its target; in parallel on the host threads), and the values
// are added onto their targets in raw order: on the host as they come, on the device through
// the values sorted by target (a stable radix sort, once per pattern), so that every entry
// receives the same values in the same order on both, and both give the same bits.
#pragma once
#include <petscsys.h>

#include <cstddef>
#include <cstdint>
#include <vector>

#include "assembly/coo_part.hpp"
#include "device/device_runtime.hpp"

namespace dipc {

class TargetPart {
 public:
  // The matrix entry of each of the n raw entries (rows[k], cols[k]): find(row, col, hint).
  // Entries with a negative row or column are dropped. Returns how many have no entry (the
  // part is then unusable until built again). Throws std::length_error where n or a target
  // does not fit (2^31 - 1 entries, 2^32 - 2 targets).
  std::size_t build(const PetscInt* rows, const PetscInt* cols, std::size_t n, const CooPart::Find& find);
  // The targets to the device, sorted there for add_on_device; the host's copy is freed.
  void keep_on_device();

  // unique[target[k]] += raw[k], k ascending (raw: the part's first raw value).
  void add(const double* raw, double* unique) const;
  void add_on_device(const double* d_raw, double* d_unique) const;

 private:
  static constexpr std::uint32_t kDropped = 0xffffffffu;
  std::vector<std::uint32_t> target_;
  std::size_t num_raw_ = 0;
  device::Array<std::uint32_t> d_keys_{"changing part's targets, sorted"};
  device::Array<std::uint32_t> d_sources_{"changing part's raw values by target"};
};

}  // namespace dipc
