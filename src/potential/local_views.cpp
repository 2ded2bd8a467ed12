#include "potential/local_views.hpp"

#include <cstring>

namespace dipc {

PetscErrorCode LocalViews::begin(Vec v) {
  PetscFunctionBeginUser;
  PetscCall(end());
  PetscInt n;
  PetscCall(VecGetLocalSize(v, &n));
  PetscCall(VecGetArrayReadAndMemType(v, &array_, &type_));
  v_ = v;
  n_ = static_cast<std::size_t>(n);
  host_ready_ = device_ready_ = false;
  PetscFunctionReturn(0);
}

PetscErrorCode LocalViews::end() {
  PetscFunctionBeginUser;
  if (v_) PetscCall(VecRestoreArrayReadAndMemType(v_, &array_));
  v_ = nullptr;
  array_ = nullptr;
  PetscFunctionReturn(0);
}

const double* LocalViews::in(MemorySpace space) {
  const bool native_host = PetscMemTypeHost(type_);
  if ((space == MemorySpace::host) == native_host) return array_;
  if (space == MemorySpace::host) {
    if (!host_ready_) {
      host_mirror_.resize(n_);
      device::copy_to_host(host_mirror_.data(), array_, n_ * sizeof(double));
      host_ready_ = true;
    }
    return host_mirror_.data();
  }
  if (!device_ready_) {
    device_mirror_.upload(array_, n_);
    device_ready_ = true;
  }
  return device_mirror_.data();
}

void copy_between(MemorySpace to_space, double* to, MemorySpace from_space, const double* from, std::size_t n) {
  if (n == 0) return;
  const std::size_t bytes = n * sizeof(double);
  if (to_space == MemorySpace::host && from_space == MemorySpace::host)
    std::memcpy(to, from, bytes);
  else if (to_space == MemorySpace::host)
    device::copy_to_host(to, from, bytes);
  else if (from_space == MemorySpace::host)
    device::copy_to_device(to, from, bytes);
  else
    device::copy_on_device(to, from, bytes);
}

}  // namespace dipc
