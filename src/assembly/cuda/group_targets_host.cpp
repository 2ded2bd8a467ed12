// group_targets.hpp for builds without CUDA: throws, naming the build option.
#include "assembly/cuda/group_targets.hpp"

#include "device/device_runtime.hpp"

namespace dipc::device {

std::size_t map_node_groups(const NodeGroupView*, const std::uint64_t*, std::size_t, const BlockEntryIndex&,
                            std::uint32_t, std::uint32_t*) {
  throw DeviceError("node group targets: dipc was built without CUDA (configure with -DDIPC_WITH_CUDA=ON)");
}

}  // namespace dipc::device
