#include "assembly/block_entries.hpp"

namespace dipc {

std::int64_t BlockEntries::find_extra(PetscInt row, PetscInt col) const {
  const std::vector<PetscInt>& rows = *extra_rows;
  const std::vector<PetscInt>& cols = *extra_cols;
  std::size_t lo = 0, hi = rows.size();
  while (lo < hi) {
    const std::size_t mid = (lo + hi) / 2;
    if (rows[mid] < row || (rows[mid] == row && cols[mid] < col))
      lo = mid + 1;
    else
      hi = mid;
  }
  if (lo < rows.size() && rows[lo] == row && cols[lo] == col)
    return static_cast<std::int64_t>(blocks->num_entries() + lo);
  return -1;
}

void BlockEntries::find(std::int64_t row_node, std::int64_t col_node, std::size_t* row_hint,
                        std::int64_t entry[9]) const {
  // The element blocks hold most (a contact pair's nodes on one body share elements), the
  // reserve the rest; the fixed part's extra entries are few (none where every node has an
  // element).
  const std::int64_t k = blocks->find_block(row_node, col_node, row_hint);
  const unsigned held = k >= 0 ? blocks->block_mask[static_cast<std::size_t>(k)] : 0u;
  ReservedBlocks::Block reserved;
  if (held != 0x1ffu) reserved = reserve->find_block(row_node, col_node);
  for (int bit = 0; bit < 9; ++bit) {
    if (held >> bit & 1u) {
      entry[bit] = static_cast<std::int64_t>(blocks->block_start[static_cast<std::size_t>(k)]) +
                   entry_in_block(held, bit);
    } else if (reserved.mask >> bit & 1u) {
      entry[bit] = static_cast<std::int64_t>(reserved.start) + entry_in_block(reserved.mask, bit);
    } else {
      entry[bit] = find_extra(static_cast<PetscInt>(3 * row_node + bit / 3),
                              static_cast<PetscInt>(3 * col_node + bit % 3));
    }
  }
}

}  // namespace dipc
