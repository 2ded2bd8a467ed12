#include "forms/body_force_form.hpp"

namespace dipc {

std::vector<double> scaled_body_forces(const std::vector<double>& node_mass, int num_owned_nodes,
                                       const std::array<double, 3>& acceleration, double scale) {
  std::vector<double> force(3 * static_cast<std::size_t>(num_owned_nodes));
  for (int i = 0; i < num_owned_nodes; ++i)
    for (int c = 0; c < 3; ++c) force[3 * i + c] = scale * node_mass[i] * acceleration[c];
  return force;
}

BodyForceForm::BodyForceForm(const std::vector<double>& node_mass, int num_owned_nodes,
                             const std::array<double, 3>& acceleration, double scale, MemorySpace space)
    : node_mass_(node_mass.begin(), node_mass.begin() + num_owned_nodes),
      acceleration_(acceleration),
      force_(scaled_body_forces(node_mass, num_owned_nodes, acceleration, scale)) {
  if (space == MemorySpace::device) device_ = std::make_unique<DeviceBodyForcePart>(force_);
}

void BodyForceForm::set_time_step(double h) {
  force_ = scaled_body_forces(node_mass_, static_cast<int>(node_mass_.size()), acceleration_, h * h);
  if (device_) device_->set_force(force_);
}

bool BodyForceForm::value(const double* x, double* energy) {
  if (device_) return device_->value(x, energy);
  double e = 0;
  for (std::size_t k = 0; k < force_.size(); ++k) e -= force_[k] * x[k];
  *energy = e;
  return true;
}

bool BodyForceForm::gradient(const double*, double* g) {
  if (device_) return device_->gradient(g);
  for (std::size_t k = 0; k < force_.size(); ++k) g[k] -= force_[k];
  return true;
}

void BodyForceForm::coo_pattern(std::vector<PetscInt>* rows, std::vector<PetscInt>* cols) {
  rows->clear();
  cols->clear();
}

}  // namespace dipc
