// node_block_pattern.hpp for builds without CUDA: throws, naming the build option.
#include "assembly/cuda/node_block_pattern.hpp"

namespace dipc::device {

void build_node_blocks(const NodeBlockForm*, int, std::size_t, const std::int64_t*, NodeBlocks*) {
  throw DeviceError("node-block pattern: dipc was built without CUDA (configure with -DDIPC_WITH_CUDA=ON)");
}

}  // namespace dipc::device
