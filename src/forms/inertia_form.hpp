// InertiaForm: ½ (x − x̂)ᵀ M (x − x̂), the kinetic part of the implicit-Euler incremental
// potential (docs/design.md §1.1; Kane et al. 2000, variational implicit Euler), x̂ = x_n + h v_n.
// Lumped M (diagonal, row-sum of the consistent mass) by default, consistent as an option.
#pragma once
#include <memory>

#include "forms/device_form_parts.hpp"
#include "forms/element_data.hpp"
#include "forms/form.hpp"

namespace dipc {

// The diagonal pattern (3·node_offset + k, same) of this rank's num_owned_dofs owned dofs: the
// lumped mass's Hessian.
void owned_diagonal_pattern(std::size_t num_owned_dofs, std::int64_t node_offset, std::vector<PetscInt>* rows,
                            std::vector<PetscInt>* cols);

class LumpedInertiaForm : public Form {
 public:
  // node_mass: complete lumped mass of every local node (contributions of all ranks summed).
  // space: where value, gradient and hessian run (device: through a DeviceLumpedInertiaPart).
  LumpedInertiaForm(std::vector<double> node_mass, int num_owned_nodes, std::int64_t node_offset,
                    MemorySpace space = MemorySpace::host);
  std::string name() const override { return "inertia (lumped)"; }
  MemorySpace memory_space() const override { return device_ ? MemorySpace::device : MemorySpace::host; }
  bool value(const double* x, double* energy) override;
  bool gradient(const double* x, double* g) override;
  void coo_pattern(std::vector<PetscInt>* rows, std::vector<PetscInt>* cols) override;
  bool hessian(const double* x, double* values) override;
  void begin_step(const double* x_hat) override;

 private:
  std::vector<double> mass_;
  std::vector<double> x_hat_;  // owned nodes only
  int num_owned_;
  std::int64_t node_offset_;
  std::unique_ptr<DeviceLumpedInertiaPart> device_;  // device space only
};

class ConsistentInertiaForm : public Form {
 public:
  // space: where value, gradient and hessian run (device: through a DeviceConsistentInertiaPart).
  explicit ConsistentInertiaForm(const ElementData& elements, MemorySpace space = MemorySpace::host);
  std::string name() const override { return "inertia (consistent)"; }
  MemorySpace memory_space() const override { return device_ ? MemorySpace::device : MemorySpace::host; }
  bool value(const double* x, double* energy) override;
  bool gradient(const double* x, double* g) override;
  void coo_pattern(std::vector<PetscInt>* rows, std::vector<PetscInt>* cols) override;
  bool hessian(const double* x, double* values) override;
  bool element_pattern(ElementPattern* pattern) const override {
    *pattern = elements_.pattern(ElementLayout::consistent_mass);
    return true;
  }
  bool element_hessian(const double* x, int first, int count, double* values) override;
  void begin_step(const double* x_hat) override;

 private:
  const ElementData& elements_;
  std::vector<double> element_mass_;                     // 64 per element: 8×8 scalar M_ab
  std::vector<double> x_hat_;                            // all local nodes
  std::unique_ptr<DeviceConsistentInertiaPart> device_;  // device space only
};

}  // namespace dipc
