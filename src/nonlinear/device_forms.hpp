// The element and nodal forms on the CUDA device (memory_space() == device): the same terms as
// ElasticForm, LumpedInertiaForm, ConsistentInertiaForm and BodyForceForm, evaluated by the
// kernels of assembly/cuda/element_kernels.hpp on device copies of their data. x, g and the
// Hessian values they receive are device pointers (form.hpp); only energies and validity come
// back to the host. The Hessians of the inertia forms are constant, so their COO values are
// computed once on the host and copied on the device at every assembly.
#pragma once
#include <array>

#include "device/device_runtime.hpp"
#include "nonlinear/element_data.hpp"
#include "nonlinear/form.hpp"

namespace dipc {

// Device copies of an ElementData block (connectivity, reference coordinates, material).
class DeviceElementData {
 public:
  explicit DeviceElementData(const ElementData& elements);
  ElementBlock block() const;  // device pointers
  std::size_t bytes() const;

 private:
  int num_elements_;
  device::Array<std::int32_t> nodes_{"element connectivity"};
  device::Array<double> reference_{"reference coordinates"}, lambda_{"lambda"}, mu_{"mu"};
  device::Array<VolumetricTerm> volumetric_{"volumetric term"};  // empty: all at the Gauss points
  device::Array<MaterialModel> model_{"material model"};         // empty: all neo-Hookean
};

class DeviceElasticForm : public Form {
 public:
  DeviceElasticForm(const ElementData& elements, double scale);
  std::string name() const override { return "elastic"; }
  MemorySpace memory_space() const override { return MemorySpace::device; }
  bool value(const double* x, double* energy) override;
  bool gradient(const double* x, double* g) override;
  void coo_pattern(std::vector<PetscInt>* rows, std::vector<PetscInt>* cols) override;
  bool hessian(const double* x, double* values) override;
  bool element_pattern(ElementPattern* pattern) const override {
    *pattern = elements_.pattern(ElementLayout::elastic);
    return true;
  }
  bool is_valid(const double* x) override;
  void set_time_step(double h) override { scale_ = h * h; }

 private:
  const ElementData& elements_;
  DeviceElementData device_;
  double scale_;
  device::Reducer reducer_;
};

class DeviceLumpedInertiaForm : public Form {
 public:
  DeviceLumpedInertiaForm(const std::vector<double>& node_mass, int num_owned_nodes, std::int64_t node_offset);
  std::string name() const override { return "inertia (lumped)"; }
  MemorySpace memory_space() const override { return MemorySpace::device; }
  bool value(const double* x, double* energy) override;
  bool gradient(const double* x, double* g) override;
  void coo_pattern(std::vector<PetscInt>* rows, std::vector<PetscInt>* cols) override;
  bool hessian(const double* x, double* values) override;
  void begin_step(const double* x_hat) override;

 private:
  std::size_t num_dofs_;
  std::int64_t node_offset_;
  device::Array<double> mass_{"lumped masses"};  // one per owned dof
  device::Array<double> x_hat_{"predicted positions"};
  device::Reducer reducer_;
};

class DeviceConsistentInertiaForm : public Form {
 public:
  explicit DeviceConsistentInertiaForm(const ElementData& elements);
  std::string name() const override { return "inertia (consistent)"; }
  MemorySpace memory_space() const override { return MemorySpace::device; }
  bool value(const double* x, double* energy) override;
  bool gradient(const double* x, double* g) override;
  void coo_pattern(std::vector<PetscInt>* rows, std::vector<PetscInt>* cols) override;
  bool hessian(const double* x, double* values) override;
  bool element_pattern(ElementPattern* pattern) const override {
    *pattern = elements_.pattern(ElementLayout::consistent_mass);
    return true;
  }
  void begin_step(const double* x_hat) override;

 private:
  const ElementData& elements_;
  DeviceElementData device_;
  std::size_t num_local_dofs_;
  device::Array<double> element_mass_{"element masses"};  // 64 per element
  device::Array<double> hessian_{"consistent mass values"};  // 192 per element, COO order
  device::Array<double> x_hat_{"predicted positions"};
  device::Reducer reducer_;
};

class DeviceBodyForceForm : public Form {
 public:
  DeviceBodyForceForm(const std::vector<double>& node_mass, int num_owned_nodes,
                      const std::array<double, 3>& acceleration, double scale);
  std::string name() const override { return "body force"; }
  MemorySpace memory_space() const override { return MemorySpace::device; }
  bool value(const double* x, double* energy) override;
  bool gradient(const double* x, double* g) override;
  void coo_pattern(std::vector<PetscInt>* rows, std::vector<PetscInt>* cols) override;
  bool hessian(const double*, double*) override { return true; }
  void set_time_step(double h) override;

 private:
  std::vector<double> node_mass_;  // owned nodes
  std::array<double, 3> acceleration_;
  device::Array<double> force_{"body forces"};  // scale · m_i g, owned dofs
  device::Reducer reducer_;
};

}  // namespace dipc
