// friction_kernels.hpp for builds without CUDA: every pass throws, naming the option that builds
// the kernels (FrictionForm on the host never calls them).
#include "contact/cuda/friction_kernels.hpp"

#include <string>

namespace dipc::device {

namespace {
[[noreturn]] void no_cuda(const char* what) {
  throw DeviceError(std::string(what) + ": dipc was built without CUDA (configure with -DDIPC_WITH_CUDA=ON)");
}
}  // namespace

bool friction_energy(DeviceFrictionPairs&, const double*, const double*, Reducer&, double*) {
  no_cuda("friction energy on the device");
}
bool add_friction_gradient(const DeviceFrictionPairs&, const double*, const double*, double*, Reducer&) {
  no_cuda("friction gradient on the device");
}
bool friction_hessian_values(const DeviceFrictionPairs&, const double*, const double*, double*, Reducer&) {
  no_cuda("friction Hessian on the device");
}
void mark_friction_reversals(DeviceFrictionPairs&, const double*, const double*, const double*, double) {
  no_cuda("friction reversals on the device");
}

}  // namespace dipc::device
