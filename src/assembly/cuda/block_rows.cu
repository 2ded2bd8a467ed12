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

__global__ void write_block_rows_kernel(BlockRows b) {
  const std::size_t r = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  if (r >= b.num_rows || b.block_row[r] < 0) return;
  const std::size_t s = static_cast<std::size_t>(b.block_row[r]);
  const int i = static_cast<int>((b.row_begin + static_cast<std::int64_t>(r)) % 3);
  const std::int64_t row = b.row_begin + static_cast<std::int64_t>(r), node = row / 3;
  const std::int64_t end = b.row_begin + static_cast<std::int64_t>(b.num_rows);
  int d = b.diag_i[r], o = b.offd_i[r];
  const auto entry = [&](std::size_t k, int bit) {
    return b.start[k] + static_cast<std::uint64_t>(__popc(b.mask[k] & ((1u << bit) - 1u)));
  };
  std::size_t diagonal_block = b.row_start[s + 1];
  for (std::size_t k = b.row_start[s]; k < b.row_start[s + 1]; ++k)
    if (b.col[k] == node && (b.mask[k] >> (4 * i) & 1u)) {
      diagonal_block = k;
      b.diag_j[d] = static_cast<int>(row - b.row_begin);
      b.position[entry(k, 4 * i)] = static_cast<std::uint32_t>(d++);
      break;
    }
  for (std::size_t k = b.row_start[s]; k < b.row_start[s + 1]; ++k) {
    const unsigned mask = b.mask[k];
    for (int j = 0; j < 3; ++j) {
      if (!(mask >> (3 * i + j) & 1u) || (k == diagonal_block && j == i)) continue;
      const std::int64_t col = 3 * b.col[k] + j;
      if (col >= b.row_begin && col < end) {
        b.diag_j[d] = static_cast<int>(col - b.row_begin);
        b.position[entry(k, 3 * i + j)] = static_cast<std::uint32_t>(d++);
      } else {
        b.offd_j[o] = offd_index(b.col_map, b.col_map_size, col);
        b.position[entry(k, 3 * i + j)] = static_cast<std::uint32_t>(b.num_diag + o++);
      }
    }
  }
}

__global__ void fill_kernel(std::uint32_t* out, std::uint32_t value, std::size_t n) {
  const std::size_t i = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  if (i < n) out[i] = value;
}

template <class T>
__global__ void scatter_kernel(T* out, const std::uint32_t* index, const T* value, std::size_t n) {
  const std::size_t k = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  if (k < n) out[index[k]] = value[k];
}

}  // namespace

void write_block_rows(const BlockRows& rows) {
  if (!rows.num_rows) return;
  write_block_rows_kernel<<<blocks_for(rows.num_rows, kThreads), kThreads>>>(rows);
  DIPC_CUDA_CHECK_LAUNCH();
}

void fill(std::uint32_t* out, std::uint32_t value, std::size_t n) {
  if (!n) return;
  fill_kernel<<<blocks_for(n, kThreads), kThreads>>>(out, value, n);
  DIPC_CUDA_CHECK_LAUNCH();
}

void scatter(std::uint32_t* out, const std::uint32_t* index, const std::uint32_t* value, std::size_t n) {
  if (!n) return;
  scatter_kernel<<<blocks_for(n, kThreads), kThreads>>>(out, index, value, n);
  DIPC_CUDA_CHECK_LAUNCH();
}

void scatter(int* out, const std::uint32_t* index, const int* value, std::size_t n) {
  if (!n) return;
  scatter_kernel<<<blocks_for(n, kThreads), kThreads>>>(out, index, value, n);
  DIPC_CUDA_CHECK_LAUNCH();
}

}  // namespace dipc::device
