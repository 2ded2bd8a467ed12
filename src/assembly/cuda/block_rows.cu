#include "assembly/cuda/block_rows.hpp"

#include "device/cuda_check.cuh"

namespace dipc::device {

namespace {

constexpr int kThreads = 256;

// Index of col in the ascending col_map (present by construction).
__device__ int offd_index(const std::int64_t* col_map, std::size_t size, std::int64_t col) {
  std::size_t lo = 0, hi = size;
  while (lo < hi) {
    const std::size_t mid = (lo + hi) / 2;
    if (col_map[mid] < col)
      lo = mid + 1;
    else
      hi = mid;
  }
  return static_cast<int>(lo);
}

// The reserve's blocks of row r: [*first, *last), empty without a reserve.
__device__ void reserve_range(const BlockRows& b, std::size_t r, std::size_t* first, std::size_t* last) {
  *first = *last = 0;
  if (!b.reserve_first) return;
  *first = b.reserve_first[r / 3], *last = b.reserve_first[r / 3 + 1];
}

// f(entry, col, in_diag, place) for each entry of block row r, in the row's order: the diagonal
// first, then the other columns ascending (the element blocks and the reserve's merged by
// column node); place counts on from diag_i[r] in the diagonal block and from offd_i[r] in the
// off-diagonal block.
template <class F>
__device__ void walk_block_row(const BlockRows& b, std::size_t r, F&& f) {
  const std::size_t s = static_cast<std::size_t>(b.block_row[r]);
  const std::int64_t row = b.row_begin + static_cast<std::int64_t>(r), node = row / 3;
  const int i = static_cast<int>(row % 3);
  const std::int64_t end = b.row_begin + static_cast<std::int64_t>(b.num_rows);
  int d = b.diag_i[r], o = b.offd_i[r];
  const auto entry = [](std::uint32_t start, unsigned mask, int bit) {
    return static_cast<std::size_t>(start) + static_cast<std::size_t>(__popc(mask & ((1u << bit) - 1u)));
  };
  const std::size_t k0 = b.row_start[s], k1 = b.row_start[s + 1];
  std::size_t e0, e1;
  reserve_range(b, r, &e0, &e1);
  bool diagonal = false;
  for (std::size_t k = k0; k < k1 && !diagonal; ++k)
    if (static_cast<std::int64_t>(b.col[k]) == node && (b.mask[k] >> (4 * i) & 1u)) {
      f(entry(b.start[k], b.mask[k], 4 * i), row, true, d++);
      diagonal = true;
    }
  for (std::size_t e = e0; e < e1 && !diagonal; ++e)
    if (b.reserve_col[e] == node && (b.reserve_mask[e] >> (4 * i) & 1u)) {
      f(entry(b.reserve_start[e], b.reserve_mask[e], 4 * i), row, true, d++);
      diagonal = true;
    }
  std::size_t k = k0, e = e0;
  while (k < k1 || e < e1) {
    const std::int64_t col_node = k < k1 && (e == e1 || static_cast<std::int64_t>(b.col[k]) <= b.reserve_col[e])
                                      ? static_cast<std::int64_t>(b.col[k])
                                      : b.reserve_col[e];
    const bool in_k = k < k1 && static_cast<std::int64_t>(b.col[k]) == col_node;
    const bool in_e = e < e1 && b.reserve_col[e] == col_node;
    const unsigned held = in_k ? b.mask[k] : 0u, reserved = in_e ? b.reserve_mask[e] : 0u;
    for (int j = 0; j < 3; ++j) {
      const int bit = 3 * i + j;
      const std::int64_t col = 3 * col_node + j;
      if (col == row) continue;  // the diagonal, first
      std::size_t at;
      if (held >> bit & 1u)
        at = entry(b.start[k], held, bit);
      else if (reserved >> bit & 1u)
        at = entry(b.reserve_start[e], reserved, bit);
      else
        continue;
      if (col >= b.row_begin && col < end)
        f(at, col, true, d++);
      else
        f(at, col, false, o++);
    }
    if (in_k) ++k;
    if (in_e) ++e;
  }
}

__global__ void write_block_rows_kernel(BlockRows b, const std::int64_t* col_map, std::size_t col_map_size, int* diag_j,
                                        int* offd_j) {
  const std::size_t r = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  if (r >= b.num_rows || b.block_row[r] < 0) return;
  walk_block_row(b, r, [&](std::size_t, std::int64_t col, bool in_diag, int place) {
    if (in_diag)
      diag_j[place] = static_cast<int>(col - b.row_begin);
    else
      offd_j[place] = offd_index(col_map, col_map_size, col);
  });
}

// One warp per row: each lane takes a block (32 at a time) and writes its entries of the row,
// their places from warp prefix sums of the blocks' counts, the walk's order without walking:
// the diagonal at diag_i[r], then the other entries in block order. A thread per row walking its
// blocks read and wrote 8 B at a time far from its neighbours' (15 ms per assembly at 1M hexes
// against 2 ms for a scatter by stored positions); a warp's lanes read and write side by side.
__global__ void write_block_row_values_kernel(BlockRows b, const double* values, double* diag, double* offd) {
  constexpr unsigned kAll = 0xffffffffu;
  const std::size_t r = (blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x) / 32;
  const int lane = static_cast<int>(threadIdx.x % 32);
  if (r >= b.num_rows || b.block_row[r] < 0) return;  // the same for the whole warp
  std::size_t e0, e1;
  reserve_range(b, r, &e0, &e1);
  if (e0 < e1) return;  // a row with reserve blocks: write_reserve_row_values_kernel
  const std::size_t s = static_cast<std::size_t>(b.block_row[r]);
  const std::int64_t row = b.row_begin + static_cast<std::int64_t>(r), node = row / 3;
  const int i = static_cast<int>(row % 3);
  const std::int64_t node_begin = b.row_begin / 3, node_end = (b.row_begin + static_cast<std::int64_t>(b.num_rows)) / 3;
  const std::size_t k0 = b.row_start[s], k1 = b.row_start[s + 1];
  bool has_diagonal = false;
  for (std::size_t base = k0; base < k1; base += 32) {
    const std::size_t k = base + static_cast<std::size_t>(lane);
    const bool here = k < k1 && static_cast<std::int64_t>(b.col[k]) == node && (b.mask[k] >> (4 * i) & 1u);
    has_diagonal = has_diagonal || __ballot_sync(kAll, here) != 0u;
  }
  int next_diag = b.diag_i[r] + (has_diagonal ? 1 : 0), next_offd = b.offd_i[r];
  for (std::size_t base = k0; base < k1; base += 32) {
    const std::size_t k = base + static_cast<std::size_t>(lane);
    const bool active = k < k1;
    const unsigned mask = active ? b.mask[k] : 0u;
    const std::int64_t col_node = active ? static_cast<std::int64_t>(b.col[k]) : node;
    const unsigned row_bits = mask >> (3 * i) & 7u;
    const bool diagonal_block = active && col_node == node && (row_bits >> i & 1u);
    // A rank's rows start and end at a node: a block's columns are all in the diagonal block or none.
    const bool in_diag = col_node >= node_begin && col_node < node_end;
    const int count = __popc(row_bits) - (diagonal_block ? 1 : 0);
    int sum_diag = in_diag ? count : 0, sum_offd = in_diag ? 0 : count;
    for (int offset = 1; offset < 32; offset *= 2) {
      const int d = __shfl_up_sync(kAll, sum_diag, offset), o = __shfl_up_sync(kAll, sum_offd, offset);
      if (lane >= offset) sum_diag += d, sum_offd += o;
    }
    int place_diag = next_diag + sum_diag - (in_diag ? count : 0),
        place_offd = next_offd + sum_offd - (in_diag ? 0 : count);
    for (int j = 0; j < 3; ++j) {
      if (!(row_bits >> j & 1u)) continue;
      const double v = values[b.start[k] + static_cast<std::uint64_t>(__popc(mask & ((1u << (3 * i + j)) - 1u)))];
      if (diagonal_block && j == i)
        diag[b.diag_i[r]] = v;
      else if (in_diag)
        diag[place_diag++] = v;
      else
        offd[place_offd++] = v;
    }
    next_diag += __shfl_sync(kAll, sum_diag, 31);
    next_offd += __shfl_sync(kAll, sum_offd, 31);
  }
}

// The rows with reserve blocks (the contact pairs' nodes, a small part of the rows): one thread
// per row walks its two block lists merged.
__global__ void write_reserve_row_values_kernel(BlockRows b, const double* values, double* diag, double* offd) {
  const std::size_t r = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  if (r >= b.num_rows || b.block_row[r] < 0) return;
  std::size_t e0, e1;
  reserve_range(b, r, &e0, &e1);
  if (e0 == e1) return;
  walk_block_row(b, r, [&](std::size_t entry, std::int64_t, bool in_diag, int place) {
    (in_diag ? diag : offd)[place] = values[entry];
  });
}

template <class T>
__global__ void scatter_kernel(T* out, const std::uint32_t* index, const T* value, std::size_t n) {
  const std::size_t k = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  if (k < n) out[index[k]] = value[k];
}

}  // namespace

void write_block_rows(const BlockRows& rows, const std::int64_t* col_map, std::size_t col_map_size, int* diag_j,
                      int* offd_j) {
  if (!rows.num_rows) return;
  write_block_rows_kernel<<<blocks_for(rows.num_rows, kThreads), kThreads>>>(rows, col_map, col_map_size, diag_j,
                                                                             offd_j);
  DIPC_CUDA_CHECK_LAUNCH();
}

void write_block_row_values(const BlockRows& rows, const double* values, double* diag, double* offd) {
  if (!rows.num_rows) return;
  write_block_row_values_kernel<<<blocks_for(32 * rows.num_rows, kThreads), kThreads>>>(rows, values, diag, offd);
  DIPC_CUDA_CHECK_LAUNCH();
  if (!rows.reserve_first) return;
  write_reserve_row_values_kernel<<<blocks_for(rows.num_rows, kThreads), kThreads>>>(rows, values, diag, offd);
  DIPC_CUDA_CHECK_LAUNCH();
}

void scatter(int* out, const std::uint32_t* index, const int* value, std::size_t n) {
  if (!n) return;
  scatter_kernel<<<blocks_for(n, kThreads), kThreads>>>(out, index, value, n);
  DIPC_CUDA_CHECK_LAUNCH();
}

}  // namespace dipc::device
