// The CSR rows of a matrix whose rows are made of node blocks (NodeBlockReduction's pattern),
// written on the device: DirectMatrix's hypre matrix on the GPU. On the host this was one core
// writing a position and a column per nonzero (250M at 1M hexes) and 2 GB copied to the device
// (docs/performance.md, "Setup"); here one thread writes each row.
#pragma once
#include <cstddef>
#include <cstdint>

namespace dipc::device {

// Row r (of num_rows, global row row_begin + r = 3 node + i) with block_row[r] >= 0 is the
// i-th row of node block row s = block_row[r]: blocks k in [row_start[s], row_start[s + 1]),
// column node col[k], entries present mask[k] (bit 3i + j), first entry start[k] (an entry's
// index is start[k] + the rank of its bit in mask[k]); and, where reserve_first is not null,
// of the reserve's blocks b in [reserve_first[q], reserve_first[q + 1]) of its node (own node q
// = r / 3), described the same way by reserve_col, reserve_mask and reserve_start (a node pair
// may be in both lists, the reserve holding the entries the element block lacks). Its diagonal
// comes first (as hypre's smoothers read a row), then its other columns ascending; those in
// [row_begin, row_begin + num_rows) are the diagonal block's, from diag_i[r], the others the
// off-diagonal block's, from offd_i[r]. Rows with block_row[r] < 0 are left alone. All pointers
// are device memory: 32-bit copies of NodeBlockReduction's arrays, the masks, starts, row starts
// and columns those the element part keeps (DirectMatrix::share_blocks) where it has them, and
// the reserve's own (ReservedBlocks::upload).
struct BlockRows {
  std::size_t num_rows = 0;
  std::int64_t row_begin = 0;
  const std::int32_t* block_row = nullptr;
  const std::uint32_t* row_start = nullptr;
  const std::uint32_t* col = nullptr;
  const std::uint16_t* mask = nullptr;
  const std::uint32_t* start = nullptr;
  const std::uint32_t* reserve_first = nullptr;
  const std::int64_t* reserve_col = nullptr;
  const std::uint16_t* reserve_mask = nullptr;
  const std::uint32_t* reserve_start = nullptr;
  const int* diag_i = nullptr;
  const int* offd_i = nullptr;
};
// The rows' columns: diag_j relative to row_begin, offd_j as the index in the ascending col_map.
void write_block_rows(const BlockRows& rows, const std::int64_t* col_map, std::size_t col_map_size, int* diag_j,
                      int* offd_j);
// The rows' values at every assembly, walked in the order write_block_rows wrote the columns:
// each entry's value, values[entry], to its place in diag or offd. This walk replaces a stored
// 4 B position per entry (992 B per hex, the largest of dipc's device arrays).
void write_block_row_values(const BlockRows& rows, const double* values, double* diag, double* offd);

// out[index[k]] = value[k] for k < n (distinct indices).
void scatter(int* out, const std::uint32_t* index, const int* value, std::size_t n);

}  // namespace dipc::device
