// LocalViews: the values of a sequential PETSc Vec (a rank's local nodal array) in the memory
// space each form evaluates in (form.hpp). The Vec's own array is used where it already lives
// (host for a CPU PETSc; device for VECCUDA with a CUDA PETSc, through PETSc's memtype-aware
// VecGetArrayReadAndMemType); the other space gets a mirror, copied at most once per begin().
#pragma once
#include <petscvec.h>

#include <vector>

#include "device/device_runtime.hpp"
#include "device/memory_space.hpp"

namespace dipc {

class LocalViews {
 public:
  LocalViews() = default;
  LocalViews(const LocalViews&) = delete;
  LocalViews& operator=(const LocalViews&) = delete;
  ~LocalViews() { end(); }

  PetscErrorCode begin(Vec v);
  PetscErrorCode end();
  const double* in(MemorySpace space);
  std::size_t size() const { return n_; }

 private:
  Vec v_ = nullptr;
  const PetscScalar* array_ = nullptr;
  PetscMemType type_ = PETSC_MEMTYPE_HOST;
  std::size_t n_ = 0;
  bool host_ready_ = false, device_ready_ = false;
  std::vector<double> host_mirror_;
  device::Array<double> device_mirror_{"local nodal array"};
};

// Copies values of n doubles between spaces (either direction, or within one).
void copy_between(MemorySpace to_space, double* to, MemorySpace from_space, const double* from, std::size_t n);

}  // namespace dipc
