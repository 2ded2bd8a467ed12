// element_kernels.hpp for builds without CUDA: every kernel throws, naming the build option.
#include "assembly/cuda/element_kernels.hpp"

namespace dipc::device {

namespace {
[[noreturn]] void no_cuda() {
  throw DeviceError("element kernels: dipc was built without CUDA (configure with -DDIPC_WITH_CUDA=ON)");
}
}  // namespace

bool elastic_evaluate(const ElementBlock&, const double*, double, double*, double*, double*, Reducer&) { no_cuda(); }
double min_volume_ratio(const ElementBlock&, const double*, Reducer&) { no_cuda(); }
double lumped_inertia_energy(const double*, const double*, const double*, std::size_t, Reducer&) { no_cuda(); }
void lumped_inertia_gradient(const double*, const double*, const double*, std::size_t, double*) { no_cuda(); }
double consistent_inertia_energy(const ElementBlock&, const double*, const double*, const double*, Reducer&) {
  no_cuda();
}
void consistent_inertia_gradient(const ElementBlock&, const double*, const double*, const double*, double*) {
  no_cuda();
}
double dot(const double*, const double*, std::size_t, Reducer&) { no_cuda(); }
void reduce_element_blocks(const double*, std::size_t, const std::uint16_t*, const std::uint32_t*,
                           const ElementBlockMap*, int, double*) {
  no_cuda();
}
void add_element_block_chunk(const double*, std::uint32_t, std::uint32_t, std::size_t, std::size_t,
                             const std::uint16_t*, const std::uint32_t*, const ElementBlockMap&, double*) {
  no_cuda();
}
void element_chunk_block_ranges(std::size_t, const ElementBlockMap&, std::uint32_t, std::size_t,
                                std::vector<std::uint64_t>*, std::vector<std::uint64_t>*) {
  no_cuda();
}

}  // namespace dipc::device
