// block_rows.hpp for builds without CUDA: throws, naming the build option.
#include "assembly/cuda/block_rows.hpp"

#include "device/device_runtime.hpp"

namespace dipc::device {

namespace {
[[noreturn]] void no_cuda() {
  throw DeviceError("block rows: dipc was built without CUDA (configure with -DDIPC_WITH_CUDA=ON)");
}
}  // namespace

void write_block_rows(const BlockRows&, const std::int64_t*, std::size_t, int*, int*) { no_cuda(); }
void write_block_row_values(const BlockRows&, const double*, double*, double*) { no_cuda(); }
void scatter(int*, const std::uint32_t*, const int*, std::size_t) { no_cuda(); }

}  // namespace dipc::device
