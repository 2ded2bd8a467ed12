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
// column node col[k], entries present mask[k] (bit 3i + j), first entry start[k]. Its diagonal
// comes first (as hypre's smoothers read a row), then its other columns ascending; those in
// [row_begin, row_begin + num_rows) go to diag_j from diag_i[r] (relative to row_begin), the
// others to offd_j from offd_i[r] (their index in the ascending col_map). Each entry's position
// goes to position[start[k] + rank of its bit in mask[k]]: its diag_j index, or num_diag + its
// offd_j index. Rows with block_row[r] < 0 are left alone. All pointers are device memory.
struct BlockRows {
  std::size_t num_rows = 0;
  std::int64_t row_begin = 0;
  const std::int64_t* block_row = nullptr;
  const std::uint64_t* row_start = nullptr;
  const std::int64_t* col = nullptr;
  const std::uint16_t* mask = nullptr;
  const std::uint64_t* start = nullptr;
  const int* diag_i = nullptr;
  const int* offd_i = nullptr;
  const std::int64_t* col_map = nullptr;
  std::size_t col_map_size = 0;
  std::size_t num_diag = 0;
  int* diag_j = nullptr;
  int* offd_j = nullptr;
  std::uint32_t* position = nullptr;
};
void write_block_rows(const BlockRows& rows);

// out[i] = value for i < n.
void fill(std::uint32_t* out, std::uint32_t value, std::size_t n);
// out[index[k]] = value[k] for k < n (distinct indices).
void scatter(std::uint32_t* out, const std::uint32_t* index, const std::uint32_t* value, std::size_t n);
void scatter(int* out, const std::uint32_t* index, const int* value, std::size_t n);

}  // namespace dipc::device
