// group_targets.hpp for builds without CUDA: throws, naming the build option.
#include "assembly/cuda/group_targets.hpp"

#include "device/device_runtime.hpp"

namespace dipc::device {

namespace {
[[noreturn]] void no_cuda() {
  throw DeviceError("node group targets: dipc was built without CUDA (configure with -DDIPC_WITH_CUDA=ON)");
}
}  // namespace

std::size_t map_node_groups(const NodeGroupView*, const std::uint64_t*, std::size_t, const BlockEntryIndex&,
                            std::uint32_t, std::uint32_t*) {
  no_cuda();
}
void reserve_node_groups(const NodeGroupView*, std::size_t, const BlockEntryIndex&, std::vector<std::int64_t>*,
                         std::vector<std::int64_t>*, std::vector<std::uint16_t>*) {
  no_cuda();
}

}  // namespace dipc::device
