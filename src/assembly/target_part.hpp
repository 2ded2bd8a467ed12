// TargetPart: a part of the Hessian's raw values (the terms whose pattern changes: contact,
// friction) mapped value by value onto the matrix's entries, without a reduction of its own.
//
// A CooPart first sums its raw values per distinct (row, col) and needs a sort of its COO list
// for that (CooReduction): O(n log n) on the host, 144 entries per contact pair, 1.5-9 s per
// active-set change on contact-rich scenes at 1M hexes on one H200's host. Here the part is
// given as node groups (hessian_pattern.hpp: a contact pair's body nodes, whose values are the
// dense block over them), each group's node blocks are looked up among the matrix's (16 per
// contact pair, in parallel on the host threads, or on the device for a device matrix:
// cuda/group_targets.hpp; a lookup gives a block's 9 entries), and every raw value gets its
// entry (its target) from its block's. The values are added onto their
// targets in raw order: on the host as they come, on the device through the values sorted by
// target (a stable radix sort, once per pattern), so that every entry receives the same values
// in the same order on both, and both give the same bits.
#pragma once
#include <petscsys.h>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "assembly/cuda/group_targets.hpp"
#include "assembly/hessian_pattern.hpp"
#include "assembly/large_page_vector.hpp"
#include "device/device_runtime.hpp"

namespace dipc {

// The groups as the device reads them (the same layout, checked in target_part.cpp).
inline const device::NodeGroupView* node_group_views(const std::vector<NodeGroup>& groups) {
  return reinterpret_cast<const device::NodeGroupView*>(groups.data());
}

class TargetPart {
 public:
  // find(row_node, col_node, row_hint, entry): the matrix entries of the node block's 9 dof
  // pairs (3 row_node + i, 3 col_node + j) into entry[3i + j], -1 where the matrix has none;
  // row_hint as for NodeBlockReduction::find_block.
  using BlockFind =
      std::function<void(std::int64_t row_node, std::int64_t col_node, std::size_t* row_hint, std::int64_t entry[9])>;
  // The matrix entry of every raw value of the groups (in their order, each group's values as
  // hessian_pattern.hpp lays them out). Returns how many values have no entry (the part is then
  // unusable until built again); with stop_at_missing the threads stop at the first such value
  // and the count is only nonzero: a pattern tried against a matrix it does not fit stops
  // there instead of looking up every block (on the 1M stack over 8 steps 25 of 48 tries
  // failed, at about 0.25 s each). Throws std::length_error where the values or a target do
  // not fit (2^31 - 1 values, 2^32 - 2 targets).
  std::size_t build(const std::vector<NodeGroup>& groups, const BlockFind& find, bool stop_at_missing = false);
  // build() on the device, for a matrix whose values are summed there: the groups' blocks
  // looked up in `index` (the matrix's num_entries entries, cuda/group_targets.hpp) by the
  // device, which keeps the targets; the host's array is not written (add() then throws).
  // Returns how many values have no entry. Throws std::length_error as build() does.
  std::size_t build_on_device(const std::vector<NodeGroup>& groups, const device::BlockEntryIndex& index,
                              std::size_t num_entries);
  // The targets to the device (unless they were found there), sorted there for add_on_device.
  // Once per build: a second call keeps the device's targets.
  void keep_on_device();

  // unique[target[k]] += raw[k], k ascending (raw: the part's first raw value).
  void add(const double* raw, double* unique) const;
  void add_on_device(const double* d_raw, double* d_unique) const;

 private:
  static constexpr std::uint32_t kDropped = 0xffffffffu;
  // The first num_raw_ are the values' targets; the array is kept, and only grows, across builds.
  LargePageVector<std::uint32_t> target_;
  std::size_t num_raw_ = 0;
  bool on_device_ = false;        // keep_on_device() ran since the build
  bool built_on_device_ = false;  // the last build was build_on_device(): d_keys_ holds the targets
  // build_on_device()'s inputs on the device.
  device::Array<device::NodeGroupView> d_groups_{"changing part's node groups"};
  device::Array<std::uint64_t> d_group_begin_{"changing part's group offsets"};
  device::Array<std::uint32_t> d_keys_{"changing part's targets, sorted"};
  device::Array<std::uint32_t> d_sources_{"changing part's raw values by target"};
};

}  // namespace dipc
