#include "assembly/target_part.hpp"

#include <atomic>
#include <cstddef>
#include <limits>
#include <stdexcept>

#include "threads/host_threads.hpp"

namespace dipc {

namespace {
// Each group's first raw value, and their number at the end. Throws where the device sort, which
// counts its items in int, could not take them.
std::vector<std::uint64_t> group_begin(const std::vector<NodeGroup>& groups) {
  std::vector<std::uint64_t> begin(groups.size() + 1, 0);
  for (std::size_t g = 0; g < groups.size(); ++g) begin[g + 1] = begin[g] + node_group_values(groups[g].count);
  if (begin.back() > static_cast<std::uint64_t>(std::numeric_limits<int>::max()))
    throw std::length_error("more than 2^31 - 1 changing Hessian entries on one rank: run on more ranks");
  return begin;
}

// The device reads the host's groups as they lie in memory.
static_assert(sizeof(NodeGroup) == sizeof(device::NodeGroupView) && offsetof(NodeGroup, node) == 0 &&
                  offsetof(NodeGroup, count) == offsetof(device::NodeGroupView, count) &&
                  sizeof(NodeGroup::count) == sizeof(device::NodeGroupView::count),
              "NodeGroup and device::NodeGroupView differ in layout");
}  // namespace

std::size_t TargetPart::build(const std::vector<NodeGroup>& groups, const BlockFind& find, bool stop_at_missing) {
  const std::vector<std::uint64_t> begin = group_begin(groups);
  const std::size_t n = begin.back();
  num_raw_ = n;
  on_device_ = false;
  built_on_device_ = false;
  // Every value is written below (its target or kDropped), by the thread of its group: the
  // array is not filled first, and it is kept from build to build (grown only), so that its
  // pages are not faulted in and zeroed again at every pattern change (hundreds of MB at 1M
  // hexes; the 1M stack's pattern changes over 8 steps took 24 s with it, 35-36 s without,
  // on one H200 in two calls).
  if (target_.size() < n) target_.resize(n);
  std::vector<std::size_t> chunk_missing(static_cast<std::size_t>(host_threads()), 0);
  std::atomic<bool> too_far{false}, any_missing{false};
  const int chunks = parallel_chunks(groups.size(), [&](int c, std::size_t g0, std::size_t g1) {
    std::size_t row_hint = 0, missing = 0;
    std::int64_t entry[9];
    for (std::size_t g = g0; g < g1; ++g) {
      if (stop_at_missing && any_missing.load(std::memory_order_relaxed)) break;
      const NodeGroup& group = groups[g];
      const int n3 = 3 * group.count;
      for (int a = 0; a < group.count; ++a)
        for (int b = 0; b < group.count; ++b) {
          find(group.node[a], group.node[b], &row_hint, entry);
          for (int bit = 0; bit < 9; ++bit) {
            // Value (3a + i, 3b + j) of the group's row-major (3 count)^2 block.
            const std::size_t k = begin[g] + static_cast<std::size_t>((3 * a + bit / 3) * n3 + 3 * b + bit % 3);
            if (entry[bit] < 0) {
              target_[k] = kDropped;
              ++missing;
              if (stop_at_missing) any_missing.store(true, std::memory_order_relaxed);  // the other threads stop too
            } else if (static_cast<std::uint64_t>(entry[bit]) >= kDropped) {
              too_far = true;
            } else {
              target_[k] = static_cast<std::uint32_t>(entry[bit]);
            }
          }
        }
    }
    chunk_missing[static_cast<std::size_t>(c)] = missing;
  });
  if (too_far) throw std::length_error("more than 2^32 - 2 Hessian entries on one rank: run on more ranks");
  std::size_t missing = 0;
  for (int c = 0; c < chunks; ++c) missing += chunk_missing[static_cast<std::size_t>(c)];
  return missing;
}

std::size_t TargetPart::build_on_device(const std::vector<NodeGroup>& groups, const device::BlockEntryIndex& index,
                                        std::size_t num_entries) {
  if (num_entries >= kDropped)
    throw std::length_error("more than 2^32 - 2 Hessian entries on one rank: run on more ranks");
  const std::vector<std::uint64_t> begin = group_begin(groups);
  num_raw_ = begin.back();
  on_device_ = false;
  built_on_device_ = true;
  if (!groups.empty()) d_groups_.upload(node_group_views(groups), groups.size());
  d_group_begin_.upload(begin);
  d_keys_.resize(num_raw_);
  return device::map_node_groups(d_groups_.data(), d_group_begin_.data(), groups.size(), index, kDropped,
                                 d_keys_.data());
}

void TargetPart::keep_on_device() {
  if (on_device_) return;
  on_device_ = true;
  if (!built_on_device_) d_keys_.upload(target_.data(), num_raw_);
  d_sources_.resize(num_raw_);
  device::sort_by_target(d_keys_.data(), d_sources_.data(), num_raw_);
}

void TargetPart::add(const double* raw, double* unique) const {
  if (built_on_device_) throw std::logic_error("TargetPart::add: the targets were found on the device");
  for (std::size_t k = 0; k < num_raw_; ++k)
    if (target_[k] != kDropped) unique[target_[k]] += raw[k];
}

void TargetPart::add_on_device(const double* d_raw, double* d_unique) const {
  device::add_by_target(d_unique, d_keys_.data(), d_sources_.data(), d_raw, num_raw_);
}

}  // namespace dipc
