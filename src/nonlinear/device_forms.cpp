#include "nonlinear/device_forms.hpp"

#include "assembly/cuda/element_kernels.hpp"
#include "assembly/hex8_mass.hpp"
#include "nonlinear/body_force_form.hpp"
#include "nonlinear/inertia_form.hpp"

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

DeviceElasticForm::DeviceElasticForm(const ElementData& elements, double scale)
    : elements_(elements), device_(elements), scale_(scale) {}

bool DeviceElasticForm::value(const double* x, double* energy) {
  return device::elastic_evaluate(device_.block(), x, scale_, energy, nullptr, nullptr, reducer_);
}

bool DeviceElasticForm::gradient(const double* x, double* g) {
  return device::elastic_evaluate(device_.block(), x, scale_, nullptr, g, nullptr, reducer_);
}

void DeviceElasticForm::coo_pattern(std::vector<PetscInt>* rows, std::vector<PetscInt>* cols) {
  elements_.elastic_pattern(rows, cols);
}

bool DeviceElasticForm::hessian(const double* x, double* values) {
  return device::elastic_evaluate(device_.block(), x, scale_, nullptr, nullptr, values, reducer_);
}

bool DeviceElasticForm::is_valid(const double* x) {
  return device::min_volume_ratio(device_.block(), x, reducer_) > 0.0;
}

// ---- lumped inertia -------------------------------------------------------------------------

DeviceLumpedInertiaForm::DeviceLumpedInertiaForm(const std::vector<double>& node_mass, int num_owned_nodes,
                                                 std::int64_t node_offset)
    : num_dofs_(3 * static_cast<std::size_t>(num_owned_nodes)), node_offset_(node_offset) {
  std::vector<double> m(num_dofs_);
  for (std::size_t k = 0; k < num_dofs_; ++k) m[k] = node_mass[k / 3];
  mass_.upload(m);
  x_hat_.resize(num_dofs_);
  x_hat_.set_zero();
}

void DeviceLumpedInertiaForm::begin_step(const double* x_hat) { x_hat_.upload(x_hat, num_dofs_); }

bool DeviceLumpedInertiaForm::value(const double* x, double* energy) {
  *energy = device::lumped_inertia_energy(mass_.data(), x_hat_.data(), x, num_dofs_, reducer_);
  return true;
}

bool DeviceLumpedInertiaForm::gradient(const double* x, double* g) {
  device::lumped_inertia_gradient(mass_.data(), x_hat_.data(), x, num_dofs_, g);
  return true;
}

void DeviceLumpedInertiaForm::coo_pattern(std::vector<PetscInt>* rows, std::vector<PetscInt>* cols) {
  owned_diagonal_pattern(num_dofs_, node_offset_, rows, cols);
}

bool DeviceLumpedInertiaForm::hessian(const double*, double* values) {
  device::copy_on_device(values, mass_.data(), num_dofs_ * sizeof(double));
  return true;
}

// ---- consistent inertia ---------------------------------------------------------------------

DeviceConsistentInertiaForm::DeviceConsistentInertiaForm(const ElementData& elements)
    : elements_(elements), device_(elements), num_local_dofs_(elements.reference.size()) {
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

void DeviceConsistentInertiaForm::begin_step(const double* x_hat) { x_hat_.upload(x_hat, num_local_dofs_); }

bool DeviceConsistentInertiaForm::value(const double* x, double* energy) {
  *energy = device::consistent_inertia_energy(device_.block(), element_mass_.data(), x_hat_.data(), x, reducer_);
  return true;
}

bool DeviceConsistentInertiaForm::gradient(const double* x, double* g) {
  device::consistent_inertia_gradient(device_.block(), element_mass_.data(), x_hat_.data(), x, g);
  return true;
}

void DeviceConsistentInertiaForm::coo_pattern(std::vector<PetscInt>* rows, std::vector<PetscInt>* cols) {
  elements_.consistent_mass_pattern(rows, cols);
}

bool DeviceConsistentInertiaForm::hessian(const double*, double* values) {
  device::copy_on_device(values, hessian_.data(), hessian_.size() * sizeof(double));
  return true;
}

// ---- body force -----------------------------------------------------------------------------

DeviceBodyForceForm::DeviceBodyForceForm(const std::vector<double>& node_mass, int num_owned_nodes,
                                         const std::array<double, 3>& acceleration, double scale)
    : node_mass_(node_mass.begin(), node_mass.begin() + num_owned_nodes),
      acceleration_(acceleration) {
  force_.upload(scaled_body_forces(node_mass, num_owned_nodes, acceleration, scale));
}

void DeviceBodyForceForm::set_time_step(double h) {
  force_.upload(scaled_body_forces(node_mass_, static_cast<int>(node_mass_.size()), acceleration_, h * h));
}

bool DeviceBodyForceForm::value(const double* x, double* energy) {
  *energy = -device::dot(force_.data(), x, force_.size(), reducer_);
  return true;
}

bool DeviceBodyForceForm::gradient(const double*, double* g) {
  device::add_scaled(g, -1.0, force_.data(), force_.size());
  return true;
}

void DeviceBodyForceForm::coo_pattern(std::vector<PetscInt>* rows, std::vector<PetscInt>* cols) {
  rows->clear();
  cols->clear();
}

}  // namespace dipc
