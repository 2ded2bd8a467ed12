#include "assembly/reserved_blocks.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>

#include "threads/host_threads.hpp"

namespace dipc {

void ReservedBlocks::clear() {
  // The device arrays keep their allocations for the next upload.
  pairs_.clear(), mask_.clear(), start_.clear(), dense_first_.clear();
  dense_begin_ = dense_end_ = 0;
  num_entries_ = first_entry_ = 0;
  uploaded_ = false;
}

void ReservedBlocks::build(std::vector<NodePair>& node_pairs, const NodeBlockReduction& blocks, const Held& held,
                           std::size_t first_entry) {
  clear();
  if (!std::is_sorted(node_pairs.begin(), node_pairs.end())) std::sort(node_pairs.begin(), node_pairs.end());
  node_pairs.erase(std::unique(node_pairs.begin(), node_pairs.end()), node_pairs.end());
  // Each pair's entries that nothing holds yet, on the host threads; then the blocks in order.
  std::vector<std::uint16_t> missing(node_pairs.size());
  parallel_for(node_pairs.size(), [&](std::size_t p0, std::size_t p1) {
    std::size_t row_hint = 0;  // pairs ascend by row node
    for (std::size_t p = p0; p < p1; ++p) {
      const NodePair& pair = node_pairs[p];
      const std::int64_t k = blocks.find_block(pair[0], pair[1], &row_hint);
      unsigned m = 0x1ffu & ~(k >= 0 ? static_cast<unsigned>(blocks.block_mask[static_cast<std::size_t>(k)]) : 0u);
      for (int bit = 0; bit < 9; ++bit)
        if (m >> bit & 1u &&
            held(static_cast<PetscInt>(3 * pair[0] + bit / 3), static_cast<PetscInt>(3 * pair[1] + bit % 3)))
          m &= ~(1u << bit);
      missing[p] = static_cast<std::uint16_t>(m);
    }
  });
  std::size_t next = first_entry;
  for (std::size_t p = 0; p < node_pairs.size(); ++p) {
    if (!missing[p]) continue;
    pairs_.push_back(node_pairs[p]);
    mask_.push_back(missing[p]);
    start_.push_back(next);
    next += kBlockMaskBits[missing[p]];
  }
  finish(blocks, first_entry, next);
}

void ReservedBlocks::assign(const std::vector<std::int64_t>& rows, const std::vector<std::int64_t>& cols,
                            const std::vector<std::uint16_t>& masks, const NodeBlockReduction& blocks,
                            std::size_t first_entry) {
  clear();
  std::size_t next = first_entry;
  for (std::size_t p = 0; p < masks.size(); ++p) {
    if (!masks[p]) continue;
    pairs_.push_back({rows[p], cols[p]});
    mask_.push_back(masks[p]);
    start_.push_back(next);
    next += kBlockMaskBits[masks[p]];
  }
  finish(blocks, first_entry, next);
}

void ReservedBlocks::finish(const NodeBlockReduction& blocks, std::size_t first_entry, std::size_t end_entry) {
  num_entries_ = end_entry - first_entry;
  first_entry_ = first_entry;
  // Each dense row's first pair, in one pass over the rows and the pairs (both ascending).
  dense_begin_ = blocks.dense_begin, dense_end_ = std::max(blocks.dense_begin, blocks.dense_end);
  dense_first_.resize(static_cast<std::size_t>(dense_end_ - dense_begin_) + 1);
  std::size_t p = 0;
  for (std::size_t r = 0; r < dense_first_.size(); ++r) {
    while (p < pairs_.size() && pairs_[p][0] < dense_begin_ + static_cast<std::int64_t>(r)) ++p;
    dense_first_[r] = p;
  }
}

std::size_t ReservedBlocks::first_of_row(std::int64_t row_node) const {
  if (row_node >= dense_begin_ && row_node <= dense_end_ && !dense_first_.empty())
    return dense_first_[static_cast<std::size_t>(row_node - dense_begin_)];
  return static_cast<std::size_t>(std::lower_bound(pairs_.begin(), pairs_.end(), row_node,
                                                   [](const NodePair& p, std::int64_t r) { return p[0] < r; }) -
                                  pairs_.begin());
}

ReservedBlocks::Block ReservedBlocks::find_block(std::int64_t row_node, std::int64_t col_node) const {
  const NodePair pair{row_node, col_node};
  auto first = pairs_.begin(), last = pairs_.end();
  if (row_node >= dense_begin_ && row_node < dense_end_) {
    const std::size_t r = static_cast<std::size_t>(row_node - dense_begin_);
    first += static_cast<std::ptrdiff_t>(dense_first_[r]);
    last = pairs_.begin() + static_cast<std::ptrdiff_t>(dense_first_[r + 1]);
  }
  const auto it = std::lower_bound(first, last, pair);
  if (it == last || *it != pair) return {};
  const std::size_t k = static_cast<std::size_t>(it - pairs_.begin());
  return {mask_[k], start_[k]};
}

void ReservedBlocks::entries(std::vector<PetscInt>* rows, std::vector<PetscInt>* cols) const {
  // Block k's entries go at its start's offset from the first block's, on the host threads.
  const std::size_t at = rows->size();
  rows->resize(at + num_entries_), cols->resize(at + num_entries_);
  parallel_for(pairs_.size(), [&](std::size_t k0, std::size_t k1) {
    for (std::size_t k = k0; k < k1; ++k) {
      std::size_t e = at + (start_[k] - start_[0]);
      for (int bit = 0; bit < 9; ++bit)
        if (mask_[k] >> bit & 1u) {
          (*rows)[e] = static_cast<PetscInt>(3 * pairs_[k][0] + bit / 3);
          (*cols)[e++] = static_cast<PetscInt>(3 * pairs_[k][1] + bit % 3);
        }
    }
  });
}

void ReservedBlocks::upload() {
  constexpr std::size_t kMax = std::numeric_limits<std::uint32_t>::max();
  if (pairs_.size() > kMax || (!start_.empty() && start_.back() + 9 > kMax))
    throw std::length_error(
        "reserved Hessian blocks: more entries on one rank than 32-bit indices hold: run on more ranks");
  std::vector<std::int64_t> rows(pairs_.size()), cols(pairs_.size());
  for (std::size_t k = 0; k < pairs_.size(); ++k) rows[k] = pairs_[k][0], cols[k] = pairs_[k][1];
  d_row_.upload(rows);
  d_col_.upload(cols);
  d_mask_.upload(mask_);
  d_start_.upload(std::vector<std::uint32_t>(start_.begin(), start_.end()));
  d_dense_first_.upload(std::vector<std::uint32_t>(dense_first_.begin(), dense_first_.end()));
  uploaded_ = true;
}

bool ReservedBlocks::device_index(device::BlockEntryIndex* index) const {
  if (!uploaded_) return false;
  index->num_reserved = pairs_.size();
  index->reserve_row = d_row_.data();
  index->reserve_col = d_col_.data();
  index->reserve_mask = d_mask_.data();
  index->reserve_start = d_start_.data();
  index->reserve_dense_first = d_dense_first_.data();
  return true;
}

}  // namespace dipc
