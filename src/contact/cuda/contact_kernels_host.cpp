// contact_kernels.hpp for builds without CUDA: every pass over a device pair list throws,
// naming the option that builds the kernels (ContactForm on the host never calls them).
#include "contact/cuda/contact_kernels.hpp"

namespace dipc::device {

namespace {
[[noreturn]] void no_cuda(const char* what) {
  throw DeviceError(std::string(what) + ": dipc was built without CUDA (configure with -DDIPC_WITH_CUDA=ON)");
}
}  // namespace

bool contact_barrier_energy(const DeviceContactPairs&, const DeviceContactObstacles&, const BarrierConstants&,
                            const double*, Reducer&, double*) {
  no_cuda("contact barrier energy on the device");
}
bool add_contact_barrier_gradient(const DeviceContactPairs&, const DeviceContactObstacles&, const BarrierConstants&,
                                  const double*, double*, Reducer&) {
  no_cuda("contact barrier gradient on the device");
}
bool contact_barrier_hessian(const DeviceContactPairs&, const DeviceContactObstacles&, const BarrierConstants&,
                             const double*, double*, Reducer&) {
  no_cuda("contact barrier Hessian on the device");
}
bool contact_active_flags(const DeviceContactPairs&, const DeviceContactObstacles&, const BarrierConstants&,
                          const double*, std::int32_t*, Reducer&) {
  no_cuda("contact active set on the device");
}
double contact_min_squared_distance(const DeviceContactPairs&, const DeviceContactObstacles&, const double*, Reducer&) {
  no_cuda("contact distances on the device");
}
void contact_times_of_impact(const DeviceContactPairs&, const DeviceContactObstacles&, const double*, const double*,
                             double, double*) {
  no_cuda("contact CCD on the device");
}
double contact_min_time_of_impact(const DeviceContactPairs&, const DeviceContactObstacles&, const double*,
                                  const double*, double, Reducer&) {
  no_cuda("contact CCD on the device");
}
void build_candidate_pairs(const DevicePairSources&, const Array<std::int32_t>&,
                           const std::array<std::size_t, kNumCandidateKinds + 1>&, DeviceContactPairs*) {
  no_cuda("contact candidate pairs on the device");
}

}  // namespace dipc::device
