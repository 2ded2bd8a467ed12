// device_runtime.hpp on the CUDA runtime.
#include <cub/device/device_radix_sort.cuh>

#include <algorithm>
#include <cstdio>

#include "device/allocation_ledger.hpp"
#include "device/block_cache.hpp"
#include "device/cuda_check.cuh"

namespace dipc::device {

bool built_with_cuda() { return true; }

int device_count() {
  int n = 0;
  // No driver or no device is not an error here: the caller falls back to the CPU.
  if (cudaGetDeviceCount(&n) != cudaSuccess) {
    cudaGetLastError();
    return 0;
  }
  return n;
}

void select(int index) { DIPC_CUDA_CHECK(cudaSetDevice(index)); }

int current() {
  int d = -1;
  DIPC_CUDA_CHECK(cudaGetDevice(&d));
  return d;
}

std::string name(int index) {
  cudaDeviceProp prop;
  DIPC_CUDA_CHECK(cudaGetDeviceProperties(&prop, index));
  return prop.name;
}

MemoryInfo memory_info() {
  MemoryInfo m;
  DIPC_CUDA_CHECK(cudaMemGetInfo(&m.free_bytes, &m.total_bytes));
  return m;
}

void* allocate(std::size_t bytes, const char* what) {
  if (bytes == 0) return nullptr;
  void* p = nullptr;
  cudaError_t status = cudaMalloc(&p, bytes);
  // Blocks kept for hypre (block_cache.hpp) are given back before dipc gives up.
  if (status == cudaErrorMemoryAllocation && block_cache::empty() > 0) {
    cudaGetLastError();
    status = cudaMalloc(&p, bytes);
  }
  if (status != cudaSuccess) {
    cudaGetLastError();
    std::size_t free_bytes = 0, total = 0;
    cudaMemGetInfo(&free_bytes, &total);
    char msg[256];
    std::snprintf(msg, sizeof msg, "device allocation of %.1f MiB for %s failed (%s; %.1f of %.1f MiB free)",
                  bytes / 1048576.0, what, cudaGetErrorString(status), free_bytes / 1048576.0, total / 1048576.0);
    throw DeviceError(msg);
  }
  allocation_ledger().add(p, bytes, what);
  return p;
}

void release(void* p) noexcept {
  if (!p) return;
  allocation_ledger().remove(p);
  cudaFree(p);
}

void copy_to_device(void* dst, const void* src, std::size_t bytes) {
  DIPC_CUDA_CHECK(cudaMemcpy(dst, src, bytes, cudaMemcpyHostToDevice));
}
void copy_to_host(void* dst, const void* src, std::size_t bytes) {
  DIPC_CUDA_CHECK(cudaMemcpy(dst, src, bytes, cudaMemcpyDeviceToHost));
}
void copy_on_device(void* dst, const void* src, std::size_t bytes) {
  DIPC_CUDA_CHECK(cudaMemcpy(dst, src, bytes, cudaMemcpyDeviceToDevice));
}
void zero(void* p, std::size_t bytes) { DIPC_CUDA_CHECK(cudaMemset(p, 0, bytes)); }
void synchronize() { DIPC_CUDA_CHECK(cudaDeviceSynchronize()); }

namespace {

template <bool Min>
__global__ void reduce_kernel(const double* values, std::size_t n, double* out) {
  __shared__ double scratch[kReduceThreads];
  double v = Min ? 1e300 : 0.0;
  // Grid-stride accumulation in a fixed order per thread, then a fixed-shape tree.
  for (std::size_t i = blockIdx.x * blockDim.x + threadIdx.x; i < n; i += gridDim.x * blockDim.x)
    v = Min ? fmin(v, values[i]) : v + values[i];
  const double r = Min ? block_min(v, scratch) : block_sum(v, scratch);
  if (threadIdx.x == 0) out[blockIdx.x] = r;
}

__global__ void axpy_into_kernel(double* w, const double* x, double alpha, const double* p, std::size_t n) {
  const std::size_t i = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  if (i < n) w[i] = __dadd_rn(__dmul_rn(alpha, p[i]), x[i]);
}

__global__ void add_scaled_kernel(double* y, double s, const double* x, std::size_t n) {
  const std::size_t i = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  if (i < n) y[i] += s * x[i];
}

__global__ void zero_at_kernel(double* values, const std::size_t* index, std::size_t count) {
  const std::size_t k = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  if (k < count) values[index[k]] = 0.0;
}

__global__ void one_at_kernel(double* values, const std::size_t* index, std::size_t count) {
  const std::size_t k = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  if (k < count) values[index[k]] = 1.0;
}

__global__ void add_at_kernel(double* values, const std::size_t* index, const double* add, std::size_t n,
                              std::size_t fresh_from) {
  const std::size_t k = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  if (k >= n) return;
  const std::size_t u = index[k];
  values[u] = (u < fresh_from ? values[u] : 0.0) + add[k];
}

__device__ inline double& split_at(double* diag, std::size_t num_diag, double* offd, std::size_t p) {
  return p < num_diag ? diag[p] : offd[p - num_diag];
}

__global__ void scatter_split_kernel(const double* values, const std::uint32_t* entry, const std::uint32_t* pos,
                                     std::size_t n, double* diag, std::size_t num_diag, double* offd) {
  const std::size_t k = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  if (k < n) split_at(diag, num_diag, offd, pos[k]) = values[entry[k]];
}

__global__ void gather_kernel(double* out, const double* values, const std::uint32_t* index, std::size_t n) {
  const std::size_t k = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  if (k < n) out[k] = values[index[k]];
}

__global__ void add_split_kernel(const double* add, const std::uint32_t* pos, const std::uint8_t* keep, std::size_t n,
                                 double* diag, std::size_t num_diag, double* offd) {
  const std::size_t s = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  if (s >= n) return;
  double& v = split_at(diag, num_diag, offd, pos[s]);
  v = (keep[s] ? v : 0.0) + add[s];
}

// One thread per unique entry: an entry sums few raw ones (the element blocks sharing it, at
// most 8, and the inertia and contact terms), so the serial sum is short, in the map's order.
__global__ void reduce_coo_kernel(const double* raw, const std::uint32_t* offsets, const std::uint32_t* sources,
                                  std::size_t num_unique, double* unique) {
  const std::size_t u = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  if (u >= num_unique) return;
  double sum = 0.0;
  for (std::uint32_t j = offsets[u]; j < offsets[u + 1]; ++j) sum += raw[sources[j]];
  unique[u] = sum;
}

__global__ void iota_kernel(std::uint32_t* v, std::size_t n) {
  const std::size_t k = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  if (k < n) v[k] = static_cast<std::uint32_t>(k);
}

// One thread per run of equal keys (started by its first element): the run's values in order.
// Runs are short (the contributions to one matrix entry), so the serial loop costs little.
__global__ void add_by_target_kernel(double* values, const std::uint32_t* keys, const std::uint32_t* sources,
                                     const double* raw, std::size_t n) {
  const std::size_t i = blockIdx.x * static_cast<std::size_t>(blockDim.x) + threadIdx.x;
  if (i >= n) return;
  const std::uint32_t key = keys[i];
  if (key == 0xffffffffu || (i > 0 && keys[i - 1] == key)) return;
  double sum = values[key];
  for (std::size_t j = i; j < n && keys[j] == key; ++j) sum += raw[sources[j]];
  values[key] = sum;
}

}  // namespace

// Two passes: at most 1024 blocks of partials, then one block over those.
template <bool Min>
static double reduce(const double* values, std::size_t n, Array<double>& partials, Array<double>& result) {
  if (n == 0) return Min ? 1e300 : 0.0;
  const unsigned blocks = std::min<unsigned>(1024, blocks_for(n, kReduceThreads));
  partials.resize(blocks);
  result.resize(1);
  reduce_kernel<Min><<<blocks, kReduceThreads>>>(values, n, partials.data());
  DIPC_CUDA_CHECK_LAUNCH();
  reduce_kernel<Min><<<1, kReduceThreads>>>(partials.data(), blocks, result.data());
  DIPC_CUDA_CHECK_LAUNCH();
  double r;
  result.download(&r);
  return r;
}

double Reducer::sum(const double* values, std::size_t n) { return reduce<false>(values, n, partials_, result_); }
double Reducer::min(const double* values, std::size_t n) { return reduce<true>(values, n, partials_, result_); }

double* Reducer::partials(std::size_t num_blocks) {
  partials_.resize(num_blocks);
  return partials_.data();
}

double Reducer::sum_partials(std::size_t num_blocks) {
  result_.resize(1);
  if (num_blocks == 0) return 0.0;
  reduce_kernel<false><<<1, kReduceThreads>>>(partials_.data(), num_blocks, result_.data());
  DIPC_CUDA_CHECK_LAUNCH();
  double r;
  result_.download(&r);
  return r;
}

double Reducer::min_partials(std::size_t num_blocks) {
  result_.resize(1);
  if (num_blocks == 0) return 1e300;
  reduce_kernel<true><<<1, kReduceThreads>>>(partials_.data(), num_blocks, result_.data());
  DIPC_CUDA_CHECK_LAUNCH();
  double r;
  result_.download(&r);
  return r;
}

int* Reducer::flag() {
  if (flag_.size() == 0) {
    flag_.resize(1);
    flag_.set_zero();
  }
  return flag_.data();
}
void Reducer::reset_flag() {
  flag();
  flag_.set_zero();
}
bool Reducer::flag_set() {
  int f = 0;
  flag();
  flag_.download(&f);
  return f != 0;
}

void axpy_into(double* w, const double* x, double alpha, const double* p, std::size_t n) {
  if (!n) return;
  axpy_into_kernel<<<blocks_for(n, 256), 256>>>(w, x, alpha, p, n);
  DIPC_CUDA_CHECK_LAUNCH();
}

void add_scaled(double* y, double s, const double* x, std::size_t n) {
  if (!n) return;
  add_scaled_kernel<<<blocks_for(n, 256), 256>>>(y, s, x, n);
  DIPC_CUDA_CHECK_LAUNCH();
}

void eliminate(double* values, const std::size_t* zero, std::size_t num_zero, const std::size_t* one,
               std::size_t num_one) {
  if (num_zero) {
    zero_at_kernel<<<blocks_for(num_zero, 256), 256>>>(values, zero, num_zero);
    DIPC_CUDA_CHECK_LAUNCH();
  }
  if (num_one) {
    one_at_kernel<<<blocks_for(num_one, 256), 256>>>(values, one, num_one);
    DIPC_CUDA_CHECK_LAUNCH();
  }
}

void add_at(double* values, const std::size_t* index, const double* add, std::size_t n, std::size_t fresh_from) {
  if (!n) return;
  add_at_kernel<<<blocks_for(n, 256), 256>>>(values, index, add, n, fresh_from);
  DIPC_CUDA_CHECK_LAUNCH();
}

void sort_by_target(std::uint32_t* keys, std::uint32_t* sources, std::size_t n) {
  if (!n) return;
  Array<std::uint32_t> items("sort items"), sorted_keys("sorted keys");
  items.resize(n), sorted_keys.resize(n);
  iota_kernel<<<blocks_for(n, 256), 256>>>(items.data(), n);
  DIPC_CUDA_CHECK_LAUNCH();
  // CUB's radix sort is stable: equal keys keep their sources ascending.
  std::size_t bytes = 0;
  DIPC_CUDA_CHECK(cub::DeviceRadixSort::SortPairs(nullptr, bytes, keys, sorted_keys.data(), items.data(), sources,
                                                  static_cast<int>(n)));
  Array<unsigned char> scratch("sort scratch");
  scratch.resize(std::max<std::size_t>(bytes, 1));
  DIPC_CUDA_CHECK(cub::DeviceRadixSort::SortPairs(scratch.data(), bytes, keys, sorted_keys.data(), items.data(),
                                                  sources, static_cast<int>(n)));
  copy_on_device(keys, sorted_keys.data(), n * sizeof(std::uint32_t));
}

void add_by_target(double* values, const std::uint32_t* keys, const std::uint32_t* sources, const double* raw,
                   std::size_t n) {
  if (!n) return;
  add_by_target_kernel<<<blocks_for(n, 256), 256>>>(values, keys, sources, raw, n);
  DIPC_CUDA_CHECK_LAUNCH();
}

void scatter_split(const double* values, const std::uint32_t* entry, const std::uint32_t* pos, std::size_t n,
                   double* diag, std::size_t num_diag, double* offd) {
  if (!n) return;
  scatter_split_kernel<<<blocks_for(n, 256), 256>>>(values, entry, pos, n, diag, num_diag, offd);
  DIPC_CUDA_CHECK_LAUNCH();
}

void gather(double* out, const double* values, const std::uint32_t* index, std::size_t n) {
  if (!n) return;
  gather_kernel<<<blocks_for(n, 256), 256>>>(out, values, index, n);
  DIPC_CUDA_CHECK_LAUNCH();
}

void add_split(const double* add, const std::uint32_t* pos, const std::uint8_t* keep, std::size_t n, double* diag,
               std::size_t num_diag, double* offd) {
  if (!n) return;
  add_split_kernel<<<blocks_for(n, 256), 256>>>(add, pos, keep, n, diag, num_diag, offd);
  DIPC_CUDA_CHECK_LAUNCH();
}

void reduce_coo(const double* raw, const std::uint32_t* offsets, const std::uint32_t* sources, std::size_t num_unique,
                double* unique) {
  if (!num_unique) return;
  reduce_coo_kernel<<<blocks_for(num_unique, 256), 256>>>(raw, offsets, sources, num_unique, unique);
  DIPC_CUDA_CHECK_LAUNCH();
}

}  // namespace dipc::device
