// The device halves of the element and nodal forms (ElasticForm, LumpedInertiaForm,
// ConsistentInertiaForm, BodyForceForm). A form built for MemorySpace::device holds one of
// these and dispatches its evaluations to it; each part keeps device copies of the form's data
// and calls the kernels of assembly/cuda/element_kernels.hpp. x, g and the Hessian values are
// device pointers (form.hpp); only energies and validity come back to the host. The parts are
// not Forms: the Form interface (and the COO pattern, the same in both spaces) stays with the
// one form class per term (docs/design.md §3).
#pragma once
#include <array>
#include <vector>

#include "device/device_runtime.hpp"
#include "forms/element_data.hpp"

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

// h²Ψ and its derivatives by the element kernels (scale = h²).
class DeviceElasticPart {
 public:
  explicit DeviceElasticPart(const ElementData& elements) : device_(elements) {}
  bool value(const double* x, double scale, double* energy);
  bool gradient(const double* x, double scale, double* g);
  // The values of elements [first, first + count), from element `first` on.
  bool hessian(const double* x, double scale, int first, int count, double* values);
  bool is_valid(const double* x);
  double min_volume_ratio(const double* x);

 private:
  DeviceElementData device_;
  device::Reducer reducer_;
};

// ½ Σ m_i |x_i − x̂_i|² over the owned nodes.
class DeviceLumpedInertiaPart {
 public:
  DeviceLumpedInertiaPart(const std::vector<double>& node_mass, int num_owned_nodes);
  void begin_step(const double* x_hat);  // host array of the owned dofs
  bool value(const double* x, double* energy);
  bool gradient(const double* x, double* g);
  bool hessian(double* values);

 private:
  std::size_t num_dofs_;
  device::Array<double> mass_{"lumped masses"};  // one per owned dof
  device::Array<double> x_hat_{"predicted positions"};
  device::Reducer reducer_;
};

// ½ (x − x̂)ᵀ M (x − x̂) with the consistent element masses. Its Hessian is constant: the COO
// values are computed once on the host (consistent_mass_values) and copied on the device at
// every assembly.
class DeviceConsistentInertiaPart {
 public:
  explicit DeviceConsistentInertiaPart(const ElementData& elements);
  void begin_step(const double* x_hat);  // host array of all local dofs
  bool value(const double* x, double* energy);
  bool gradient(const double* x, double* g);
  bool hessian(int first, int count, double* values);  // elements [first, first + count)

 private:
  DeviceElementData device_;
  std::size_t num_local_dofs_;
  device::Array<double> element_mass_{"element masses"};     // 64 per element
  device::Array<double> hessian_{"consistent mass values"};  // 192 per element, COO order
  device::Array<double> x_hat_{"predicted positions"};
  device::Reducer reducer_;
};

// −fᵀx with f the scaled body forces of the owned dofs.
class DeviceBodyForcePart {
 public:
  explicit DeviceBodyForcePart(const std::vector<double>& force) { set_force(force); }
  void set_force(const std::vector<double>& force) { force_.upload(force); }
  bool value(const double* x, double* energy);
  bool gradient(double* g);

 private:
  device::Array<double> force_{"body forces"};  // scale · m_i g, owned dofs
  device::Reducer reducer_;
};

}  // namespace dipc
