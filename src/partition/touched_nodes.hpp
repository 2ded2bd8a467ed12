// TouchedNodes: the input node ids that a rank's elements touch, sorted and unique, and the
// position of any id in that list (distribute_slices.cpp, rcb_partition.cpp). When the ids span
// a compact range (a box's numbering on one or a few ranks, a Gmsh mesh on one rank), a direct
// index over the range builds the list without a sort and finds an id in one step; otherwise
// (scattered ids, as in a part of a shuffled numbering on many ranks) a sort and binary
// searches. On a 1M-hex cube on one rank the sort of the 8M corner ids and the binary search
// per corner took most of the 1.1 s of distribute_slices' nodes phase. The dense path runs on
// the host threads.
#pragma once
#include <algorithm>
#include <climits>
#include <cstdint>
#include <vector>

#include "mesh/hex_mesh.hpp"
#include "threads/host_threads.hpp"

namespace dipc {

class TouchedNodes {
 public:
  // hex_of(i) gives element i's 8 input node ids, for 0 <= i < count.
  template <class HexOf>
  TouchedNodes(std::size_t count, HexOf hex_of) {
    if (count == 0) return;
    // The id range, per chunk of elements on the host threads (threads/host_threads.hpp).
    std::vector<std::int64_t> low(static_cast<std::size_t>(host_threads())), high(low.size());
    const int chunks = parallel_chunks(count, [&](int c, std::size_t begin, std::size_t end) {
      std::int64_t lo = hex_of(begin)[0], hi = lo;
      for (std::size_t e = begin; e < end; ++e)
        for (std::int64_t n : hex_of(e)) lo = std::min(lo, n), hi = std::max(hi, n);
      low[static_cast<std::size_t>(c)] = lo, high[static_cast<std::size_t>(c)] = hi;
    });
    const std::int64_t lowest = *std::min_element(low.begin(), low.begin() + chunks);
    const std::int64_t highest = *std::max_element(high.begin(), high.begin() + chunks);
    const std::int64_t span = highest - lowest + 1;
    // The index costs 4 bytes per id of the span: at most what the sort's list of 8 corner ids
    // (8 bytes each) per element would take.
    if (span <= 2 * 8 * static_cast<std::int64_t>(count) && span <= INT32_MAX)
      index_range(count, hex_of, lowest, span);
    else
      sort_corners(count, hex_of);
  }
  const std::vector<std::int64_t>& ids() const { return ids_; }
  // Position of `input` in ids(), or -1 when no element touches it.
  std::int64_t position(std::int64_t input) const {
    if (!index_.empty()) {
      const std::int64_t i = input - lowest_;
      return i >= 0 && i < static_cast<std::int64_t>(index_.size()) ? index_[static_cast<std::size_t>(i)] : -1;
    }
    const auto it = std::lower_bound(ids_.begin(), ids_.end(), input);
    return it != ids_.end() && *it == input ? it - ids_.begin() : -1;
  }

 private:
  // Marks the touched ids in the index (threads write the same 0 to shared slots, atomically),
  // then numbers them in increasing order: each chunk of the span counts its marks, and numbers
  // its own after the lower chunks'.
  template <class HexOf>
  void index_range(std::size_t count, HexOf& hex_of, std::int64_t lowest, std::int64_t span) {
    lowest_ = lowest;
    index_.assign(static_cast<std::size_t>(span), -1);
    parallel_for(count, [&](std::size_t begin, std::size_t end) {
      for (std::size_t e = begin; e < end; ++e)
        for (std::int64_t n : hex_of(e))
          __atomic_store_n(&index_[static_cast<std::size_t>(n - lowest)], 0, __ATOMIC_RELAXED);
    });
    std::vector<std::size_t> first(static_cast<std::size_t>(host_threads()), 0);
    const int chunks = parallel_chunks(index_.size(), [&](int c, std::size_t begin, std::size_t end) {
      first[static_cast<std::size_t>(c)] = static_cast<std::size_t>(
          std::count(index_.begin() + begin, index_.begin() + end, 0));
    });
    ids_.resize(chunk_starts(first, chunks)[0]);
    parallel_chunks(index_.size(), [&](int c, std::size_t begin, std::size_t end) {
      std::size_t next = first[static_cast<std::size_t>(c)];
      for (std::size_t i = begin; i < end; ++i)
        if (index_[i] == 0) {
          index_[i] = static_cast<std::int32_t>(next);
          ids_[next++] = lowest + static_cast<std::int64_t>(i);
        }
    });
  }
  template <class HexOf>
  void sort_corners(std::size_t count, HexOf& hex_of) {
    ids_.reserve(8 * count);
    for (std::size_t e = 0; e < count; ++e) {
      const Hex& hex = hex_of(e);
      ids_.insert(ids_.end(), hex.begin(), hex.end());
    }
    std::sort(ids_.begin(), ids_.end());
    ids_.erase(std::unique(ids_.begin(), ids_.end()), ids_.end());
    ids_.shrink_to_fit();
  }

  std::vector<std::int64_t> ids_;
  std::int64_t lowest_ = 0;
  std::vector<std::int32_t> index_;  // dense case: position of id lowest_ + i, or -1; empty otherwise
};

}  // namespace dipc
