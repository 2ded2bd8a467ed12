// The CUDA runtime as dipc uses it, behind a plain C++ interface so that host code (and builds
// without CUDA) never includes CUDA headers: device count and selection, memory, typed device
// arrays and the reductions that bring one scalar back. With DIPC_WITH_CUDA=OFF the same
// functions exist (device_runtime_host.cpp): device_count() is 0 and anything that would touch
// a device throws DeviceError, so callers choose the CPU path by asking, never by #ifdef.
#pragma once
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace dipc::device {

// A CUDA call failed, a device was asked for where none exists, or an allocation would not fit.
class DeviceError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// True when this build contains the CUDA kernels.
bool built_with_cuda();
// Number of usable CUDA devices (0 without a driver, a device or CUDA support).
int device_count();
// Makes `index` the current device of this process (cudaSetDevice).
void select(int index);
int current();
std::string name(int index);

struct MemoryInfo {
  std::size_t free_bytes = 0, total_bytes = 0;
};
MemoryInfo memory_info();

// Raw device allocation (cudaMalloc), bytes copied both ways, and memset to zero; `what` names
// the buffer in the error message of a failed allocation.
void* allocate(std::size_t bytes, const char* what);
void release(void* p) noexcept;
void copy_to_device(void* dst, const void* src, std::size_t bytes);
void copy_to_host(void* dst, const void* src, std::size_t bytes);
void copy_on_device(void* dst, const void* src, std::size_t bytes);
void zero(void* p, std::size_t bytes);
void synchronize();

// Owning device array of trivially copyable T. resize() discards contents; growing reallocates,
// shrinking keeps the allocation.
template <class T>
class Array {
 public:
  Array() = default;
  explicit Array(const char* what) : what_(what) {}
  Array(const Array&) = delete;
  Array& operator=(const Array&) = delete;
  Array(Array&& o) noexcept : data_(o.data_), size_(o.size_), capacity_(o.capacity_), what_(o.what_) {
    o.data_ = nullptr, o.size_ = o.capacity_ = 0;
  }
  ~Array() { release(data_); }

  void resize(std::size_t n) {
    if (n > capacity_) {
      release(data_);
      data_ = nullptr, capacity_ = 0;
      data_ = static_cast<T*>(allocate(n * sizeof(T), what_));
      capacity_ = n;
    }
    size_ = n;
  }
  void upload(const T* host, std::size_t n) {
    resize(n);
    if (n) copy_to_device(data_, host, n * sizeof(T));
  }
  template <class Allocator>
  void upload(const std::vector<T, Allocator>& host) {
    upload(host.data(), host.size());
  }
  void download(T* host) const {
    if (size_) copy_to_host(host, data_, size_ * sizeof(T));
  }
  std::vector<T> to_host() const {
    std::vector<T> h(size_);
    download(h.data());
    return h;
  }
  void set_zero() {
    if (size_) zero(data_, size_ * sizeof(T));
  }
  T* data() { return data_; }
  const T* data() const { return data_; }
  std::size_t size() const { return size_; }
  std::size_t bytes() const { return capacity_ * sizeof(T); }

 private:
  T* data_ = nullptr;
  std::size_t size_ = 0, capacity_ = 0;
  const char* what_ = "device array";
};

// Scalars reduced on the device: one kernel pass writes per-block partials into the scratch
// array, a second reduces those in a fixed order, so the result does not depend on thread
// scheduling (the line search compares energies to 1e-12).
class Reducer {
 public:
  // Sum / min of n doubles in device memory.
  double sum(const double* values, std::size_t n);
  double min(const double* values, std::size_t n);
  // Partial results of a kernel that wrote one value per block into partials(num_blocks).
  double* partials(std::size_t num_blocks);
  double sum_partials(std::size_t num_blocks);
  double min_partials(std::size_t num_blocks);
  // A device int that kernels set to 1 on failure (an inverted element); reset() zeroes it.
  int* flag();
  void reset_flag();
  bool flag_set();

 private:
  Array<double> partials_{"reduction partials"};
  Array<double> result_{"reduction result"};
  Array<int> flag_{"failure flag"};
};

// w = x + alpha * p, entry by entry, rounded as the CPU rounds it (no fused multiply-add), so
// that a trial state built on the device equals the one PETSc's VecWAXPY builds on the host.
void axpy_into(double* w, const double* x, double alpha, const double* p, std::size_t n);
// y += s * x.
void add_scaled(double* y, double s, const double* x, std::size_t n);
// values[zero[k]] = 0 for k < num_zero, then values[one[k]] = 1 for k < num_one (Dirichlet
// elimination of the matrix's entries).
void eliminate(double* values, const std::size_t* zero, std::size_t num_zero, const std::size_t* one,
               std::size_t num_one);
// values[index[k]] = (index[k] < fresh_from ? values[index[k]] : 0) + add[k] for k < n, the
// indices distinct: sums of other terms added onto entries, those from fresh_from on new ones.
void add_at(double* values, const std::size_t* index, const double* add, std::size_t n, std::size_t fresh_from);
// A matrix's values split in two arrays (a diagonal and an off-diagonal block, as AIJ and
// hypre's ParCSR keep them): position p < num_diag is diag[p], else offd[p - num_diag].
// store[pos[k]] = values[entry[k]] for k < n, the positions distinct.
void scatter_split(const double* values, const std::uint32_t* entry, const std::uint32_t* pos, std::size_t n,
                   double* diag, std::size_t num_diag, double* offd);
// out[k] = values[index[k]] for k < n.
void gather(double* out, const double* values, const std::uint32_t* index, std::size_t n);
// store[pos[s]] = (keep[s] ? store[pos[s]] : 0) + add[s] for s < n, the positions distinct.
void add_split(const double* add, const std::uint32_t* pos, const std::uint8_t* keep, std::size_t n, double* diag,
               std::size_t num_diag, double* offd);
// unique[u] = sum of raw[sources[j]] for j in [offsets[u], offsets[u+1]), added from 0 in that
// order: CooReduction::reduce on device arrays, bit for bit the same.
void reduce_coo(const double* raw, const std::uint32_t* offsets, const std::uint32_t* sources, std::size_t num_unique,
                double* unique);
// keys[k] (n values, in place) sorted ascending, stably, and sources[k] set to the position each
// had before: the values of each key in their original order.
void sort_by_target(std::uint32_t* keys, std::uint32_t* sources, std::size_t n);
// For the n (keys, sources) of sort_by_target: values[key] += raw[source] for each, in the
// sorted order (the original order within a key), keys 0xffffffff skipped.
void add_by_target(double* values, const std::uint32_t* keys, const std::uint32_t* sources, const double* raw,
                   std::size_t n);

}  // namespace dipc::device
