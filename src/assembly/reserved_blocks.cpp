#include "assembly/reserved_blocks.hpp"

#include <algorithm>

namespace dipc {

void ReservedBlocks::build(std::vector<NodePair>& node_pairs, const NodeBlockReduction& blocks, const Held& held,
                           std::size_t first_entry) {
  clear();
  std::sort(node_pairs.begin(), node_pairs.end());
  node_pairs.erase(std::unique(node_pairs.begin(), node_pairs.end()), node_pairs.end());
  std::size_t row_hint = 0, next = first_entry;  // pairs ascend by row node
  for (const NodePair& pair : node_pairs) {
    const std::int64_t k = blocks.find_block(pair[0], pair[1], &row_hint);
    unsigned missing = 0x1ffu & ~(k >= 0 ? static_cast<unsigned>(blocks.block_mask[static_cast<std::size_t>(k)]) : 0u);
    for (int bit = 0; bit < 9; ++bit)
      if (missing >> bit & 1u &&
          held(static_cast<PetscInt>(3 * pair[0] + bit / 3), static_cast<PetscInt>(3 * pair[1] + bit % 3)))
        missing &= ~(1u << bit);
    if (!missing) continue;
    pairs_.push_back(pair);
    mask_.push_back(static_cast<std::uint16_t>(missing));
    start_.push_back(next);
    next += kBlockMaskBits[missing];
  }
  num_entries_ = next - first_entry;
}

std::int64_t ReservedBlocks::find(PetscInt row, PetscInt col) const {
  if (row < 0 || col < 0) return -1;
  const NodePair pair{row / 3, col / 3};
  const auto it = std::lower_bound(pairs_.begin(), pairs_.end(), pair);
  if (it == pairs_.end() || *it != pair) return -1;
  const std::size_t k = static_cast<std::size_t>(it - pairs_.begin());
  const int bit = static_cast<int>(3 * (row % 3) + col % 3);
  if (!(mask_[k] >> bit & 1u)) return -1;
  return static_cast<std::int64_t>(start_[k]) + entry_in_block(mask_[k], bit);
}

void ReservedBlocks::entries(std::vector<PetscInt>* rows, std::vector<PetscInt>* cols) const {
  rows->reserve(rows->size() + num_entries_), cols->reserve(cols->size() + num_entries_);
  for (std::size_t k = 0; k < pairs_.size(); ++k)
    for (int bit = 0; bit < 9; ++bit)
      if (mask_[k] >> bit & 1u) {
        rows->push_back(static_cast<PetscInt>(3 * pairs_[k][0] + bit / 3));
        cols->push_back(static_cast<PetscInt>(3 * pairs_[k][1] + bit % 3));
      }
}

}  // namespace dipc
