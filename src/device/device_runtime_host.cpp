// device_runtime.hpp for builds without CUDA: no devices, and every call that would need one
// throws, naming the option that builds the kernels.
#include "device/block_cache.hpp"
#include "device/device_runtime.hpp"

namespace dipc::device {

namespace {
[[noreturn]] void no_cuda(const char* what) {
  throw DeviceError(std::string(what) + ": dipc was built without CUDA (configure with -DDIPC_WITH_CUDA=ON)");
}
}  // namespace

bool built_with_cuda() { return false; }
int device_count() { return 0; }
void select(int) { no_cuda("select device"); }
int current() { return -1; }
std::string name(int) { return "none"; }
MemoryInfo memory_info() { return {}; }
void* allocate(std::size_t bytes, const char* what) {
  if (bytes == 0) return nullptr;
  no_cuda(what);
}
void release(void*) noexcept {}
void copy_to_device(void*, const void*, std::size_t) { no_cuda("copy to device"); }
void copy_to_host(void*, const void*, std::size_t) { no_cuda("copy to host"); }
void copy_on_device(void*, const void*, std::size_t) { no_cuda("device copy"); }
void zero(void*, std::size_t) { no_cuda("device memset"); }
void synchronize() {}
double Reducer::sum(const double*, std::size_t) { no_cuda("device reduction"); }
double Reducer::min(const double*, std::size_t) { no_cuda("device reduction"); }
double* Reducer::partials(std::size_t) { no_cuda("device reduction"); }
double Reducer::sum_partials(std::size_t) { no_cuda("device reduction"); }
double Reducer::min_partials(std::size_t) { no_cuda("device reduction"); }
int* Reducer::flag() { no_cuda("device flag"); }
void Reducer::reset_flag() { no_cuda("device flag"); }
bool Reducer::flag_set() { no_cuda("device flag"); }
void axpy_into(double*, const double*, double, const double*, std::size_t) { no_cuda("device axpy"); }
void add_scaled(double*, double, const double*, std::size_t) { no_cuda("device axpy"); }
void eliminate(double*, const std::size_t*, std::size_t, const std::size_t*, std::size_t) {
  no_cuda("device elimination");
}
void add_at(double*, const std::size_t*, const double*, std::size_t, std::size_t) { no_cuda("device add_at"); }
void scatter_split(const double*, const std::uint32_t*, const std::uint32_t*, std::size_t, double*, std::size_t, double*) {
  no_cuda("device matrix values");
}
void gather(double*, const double*, const std::uint32_t*, std::size_t) { no_cuda("device gather"); }
void add_split(const double*, const std::uint32_t*, const std::uint8_t*, std::size_t, double*, std::size_t, double*) {
  no_cuda("device matrix values");
}
void reduce_coo(const double*, const std::uint32_t*, const std::uint32_t*, std::size_t, double*) {
  no_cuda("device COO reduction");
}
void sort_by_target(std::uint32_t*, std::uint32_t*, std::size_t) { no_cuda("device sort by target"); }
void add_by_target(double*, const std::uint32_t*, const std::uint32_t*, const double*, std::size_t) {
  no_cuda("device sums by target");
}

namespace block_cache {
void* allocate(std::size_t) noexcept { return nullptr; }
void release(void*) noexcept {}
std::size_t empty() noexcept { return 0; }
Stats stats() { return {}; }
}  // namespace block_cache

}  // namespace dipc::device
