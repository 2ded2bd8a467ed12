// device_broad_phase.hpp for builds without CUDA: constructing the searches is free, anything
// that would touch the device throws, naming the option that builds the kernels (ContactForm on
// the host never calls them).
#include "contact/broad_phase/cuda/device_broad_phase.hpp"

#include <string>

namespace dipc::device {

namespace {
[[noreturn]] void no_cuda(const char* what) {
  throw DeviceError(std::string(what) + ": dipc was built without CUDA (configure with -DDIPC_WITH_CUDA=ON)");
}
}  // namespace

struct DeviceBroadPhase::Impl {};

DeviceBroadPhase::DeviceBroadPhase() = default;
DeviceBroadPhase::~DeviceBroadPhase() = default;
DeviceBroadPhase::DeviceBroadPhase(DeviceBroadPhase&&) noexcept = default;
DeviceBroadPhase& DeviceBroadPhase::operator=(DeviceBroadPhase&&) noexcept = default;
void DeviceBroadPhase::upload(const BroadPhaseSurface&) { no_cuda("broad phase surface upload"); }
void DeviceBroadPhase::find_candidates(const double*, const double*, double, contact::Candidates*) {
  no_cuda("broad phase on the device");
}
void DeviceBroadPhase::find_candidates_on_segment(const double*, const double*, double, contact::Candidates*,
                                                  const PrescribedVertices&) {
  no_cuda("broad phase on the device");
}

}  // namespace dipc::device
