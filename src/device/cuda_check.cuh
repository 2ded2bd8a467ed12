// For .cu files only: CUDA error checks that throw dipc::device::DeviceError with the call and
// place, and the block-level reductions the kernels share.
#pragma once
#include <cuda_runtime.h>

#include <cstddef>
#include <string>

#include "device/device_runtime.hpp"

namespace dipc::device {

inline void check(cudaError_t status, const char* call, const char* file, int line) {
  if (status != cudaSuccess)
    throw DeviceError(std::string("CUDA error in ") + call + " (" + file + ":" + std::to_string(line) +
                      "): " + cudaGetErrorString(status));
}

// Threads per block of the reduction kernels; kernels that write partials use the same.
constexpr int kReduceThreads = 256;

// Blocks of `per_block` threads (or items) that cover n.
inline unsigned blocks_for(std::size_t n, int per_block) {
  return static_cast<unsigned>((n + per_block - 1) / per_block);
}

// Block sum / min of one value per thread; the result is valid in thread 0. `scratch` holds
// blockDim.x doubles; blockDim.x must be a power of two.
__device__ inline double block_sum(double v, double* scratch) {
  scratch[threadIdx.x] = v;
  __syncthreads();
  for (unsigned s = blockDim.x / 2; s > 0; s >>= 1) {
    if (threadIdx.x < s) scratch[threadIdx.x] += scratch[threadIdx.x + s];
    __syncthreads();
  }
  return scratch[0];
}
__device__ inline double block_min(double v, double* scratch) {
  scratch[threadIdx.x] = v;
  __syncthreads();
  for (unsigned s = blockDim.x / 2; s > 0; s >>= 1) {
    if (threadIdx.x < s) scratch[threadIdx.x] = fmin(scratch[threadIdx.x], scratch[threadIdx.x + s]);
    __syncthreads();
  }
  return scratch[0];
}

}  // namespace dipc::device

#define DIPC_CUDA_CHECK(call) ::dipc::device::check((call), #call, __FILE__, __LINE__)
// After a kernel launch: launch-configuration errors now, execution errors at the next sync.
#define DIPC_CUDA_CHECK_LAUNCH() ::dipc::device::check(cudaGetLastError(), "kernel launch", __FILE__, __LINE__)
