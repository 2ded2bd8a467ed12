// The device halves of the element and nodal forms (device_form_parts.hpp).
#include "forms/device_form_parts.hpp"

#include "assembly/cuda/element_kernels.hpp"
#include "physics/hex8_mass.hpp"

namespace dipc {

DeviceElementData::DeviceElementData(const ElementData& elements) : num_elements_(elements.num_elements()) {
  nodes_.upload(elements.nodes);
  reference_.upload(elements.reference);
  lambda_.upload(elements.lambda);
  mu_.upload(elements.mu);
  // Uploaded only when some element is not the standard one: the kernels take the plain
  // variant when block().volumetric is null.
  for (VolumetricTerm t : elements.volumetric)
    if (t != VolumetricTerm::gauss_points) {
      volumetric_.upload(elements.volumetric);
      break;
    }
  // Likewise the materials (ElementData keeps them only when some element is not neo-Hookean).
  if (!elements.model.empty()) model_.upload(elements.model);
}

ElementBlock DeviceElementData::block() const {
  ElementBlock b;
  b.num_elements = num_elements_;
  b.nodes = nodes_.data();
  b.reference = reference_.data();
  b.lambda = lambda_.data();
  b.mu = mu_.data();
  b.volumetric = volumetric_.size() ? volumetric_.data() : nullptr;
  b.model = model_.size() ? model_.data() : nullptr;
  return b;
}

std::size_t DeviceElementData::bytes() const {
  return nodes_.bytes() + reference_.bytes() + lambda_.bytes() + mu_.bytes() + volumetric_.bytes() + model_.bytes();
}

// ---- elastic ------------------------------------------------------------------------------

bool DeviceElasticPart::value(const double* x, double scale, double* energy) {
  return device::elastic_evaluate(device_.block(), x, scale, energy, nullptr, nullptr, reducer_);
}

bool DeviceElasticPart::gradient(const double* x, double scale, double* g) {
  return device::elastic_evaluate(device_.block(), x, scale, nullptr, g, nullptr, reducer_);
}

bool DeviceElasticPart::hessian(const double* x, double scale, int first, int count, double* values) {
  return device::elastic_evaluate(element_range(device_.block(), first, count), x, scale, nullptr, nullptr, values,
                                  reducer_);
}

bool DeviceElasticPart::is_valid(const double* x) { return min_volume_ratio(x) > 0.0; }

double DeviceElasticPart::min_volume_ratio(const double* x) {
  return device::min_volume_ratio(device_.block(), x, reducer_);
}

// ---- lumped inertia -------------------------------------------------------------------------

DeviceLumpedInertiaPart::DeviceLumpedInertiaPart(const std::vector<double>& node_mass, int num_owned_nodes)
    : num_dofs_(3 * static_cast<std::size_t>(num_owned_nodes)) {
  std::vector<double> m(num_dofs_);
  for (std::size_t k = 0; k < num_dofs_; ++k) m[k] = node_mass[k / 3];
  mass_.upload(m);
  x_hat_.resize(num_dofs_);
  x_hat_.set_zero();
}

void DeviceLumpedInertiaPart::begin_step(const double* x_hat) { x_hat_.upload(x_hat, num_dofs_); }

bool DeviceLumpedInertiaPart::value(const double* x, double* energy) {
  *energy = device::lumped_inertia_energy(mass_.data(), x_hat_.data(), x, num_dofs_, reducer_);
  return true;
}

bool DeviceLumpedInertiaPart::gradient(const double* x, double* g) {
  device::lumped_inertia_gradient(mass_.data(), x_hat_.data(), x, num_dofs_, g);
  return true;
}

bool DeviceLumpedInertiaPart::hessian(double* values) {
  device::copy_on_device(values, mass_.data(), num_dofs_ * sizeof(double));
  return true;
}

// ---- consistent inertia ---------------------------------------------------------------------

DeviceConsistentInertiaPart::DeviceConsistentInertiaPart(const ElementData& elements)
    : device_(elements), num_local_dofs_(elements.reference.size()) {
  const std::size_t ne = static_cast<std::size_t>(elements.num_elements());
  std::vector<double> M(64 * ne);
  for (std::size_t e = 0; e < ne; ++e) {
    double X[24];
    elements.gather_reference(static_cast<int>(e), X);
    hex8_consistent_mass(X, elements.rho[e], &M[64 * e]);
  }
  element_mass_.upload(M);
  std::vector<double> values(kMassCooPerElement * ne);
  consistent_mass_values(elements.block(), elements.rho.data(), values.data());
  hessian_.upload(values);
  x_hat_.resize(num_local_dofs_);
  x_hat_.set_zero();
}

void DeviceConsistentInertiaPart::begin_step(const double* x_hat) { x_hat_.upload(x_hat, num_local_dofs_); }

bool DeviceConsistentInertiaPart::value(const double* x, double* energy) {
  *energy = device::consistent_inertia_energy(device_.block(), element_mass_.data(), x_hat_.data(), x, reducer_);
  return true;
}

bool DeviceConsistentInertiaPart::gradient(const double* x, double* g) {
  device::consistent_inertia_gradient(device_.block(), element_mass_.data(), x_hat_.data(), x, g);
  return true;
}

bool DeviceConsistentInertiaPart::hessian(int first, int count, double* values) {
  device::copy_on_device(values, hessian_.data() + kMassCooPerElement * static_cast<std::size_t>(first),
                         kMassCooPerElement * static_cast<std::size_t>(count) * sizeof(double));
  return true;
}

// ---- body force -----------------------------------------------------------------------------

bool DeviceBodyForcePart::value(const double* x, double* energy) {
  *energy = -device::dot(force_.data(), x, force_.size(), reducer_);
  return true;
}

bool DeviceBodyForcePart::gradient(double* g) {
  device::add_scaled(g, -1.0, force_.data(), force_.size());
  return true;
}

}  // namespace dipc
