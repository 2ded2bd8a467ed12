#include "forms/inertia_form.hpp"

#include "physics/hex8_mass.hpp"

namespace dipc {

LumpedInertiaForm::LumpedInertiaForm(std::vector<double> node_mass, int num_owned_nodes, std::int64_t node_offset,
                                     MemorySpace space)
    : mass_(std::move(node_mass)),
      x_hat_(3 * static_cast<std::size_t>(num_owned_nodes), 0.0),
      num_owned_(num_owned_nodes),
      node_offset_(node_offset) {
  if (space == MemorySpace::device) device_ = std::make_unique<DeviceLumpedInertiaPart>(mass_, num_owned_nodes);
}

void LumpedInertiaForm::begin_step(const double* x_hat) {
  if (device_) return device_->begin_step(x_hat);
  x_hat_.assign(x_hat, x_hat + 3 * static_cast<std::size_t>(num_owned_));
}

bool LumpedInertiaForm::value(const double* x, double* energy) {
  if (device_) return device_->value(x, energy);
  double e = 0;
  for (int i = 0; i < num_owned_; ++i)
    for (int c = 0; c < 3; ++c) {
      const double d = x[3 * i + c] - x_hat_[3 * i + c];
      e += 0.5 * mass_[i] * d * d;
    }
  *energy = e;
  return true;
}

bool LumpedInertiaForm::gradient(const double* x, double* g) {
  if (device_) return device_->gradient(x, g);
  for (int i = 0; i < num_owned_; ++i)
    for (int c = 0; c < 3; ++c) g[3 * i + c] += mass_[i] * (x[3 * i + c] - x_hat_[3 * i + c]);
  return true;
}

void owned_diagonal_pattern(std::size_t num_owned_dofs, std::int64_t node_offset, std::vector<PetscInt>* rows,
                            std::vector<PetscInt>* cols) {
  rows->resize(num_owned_dofs);
  for (std::size_t k = 0; k < num_owned_dofs; ++k) (*rows)[k] = static_cast<PetscInt>(3 * node_offset + k);
  *cols = *rows;
}

void LumpedInertiaForm::coo_pattern(std::vector<PetscInt>* rows, std::vector<PetscInt>* cols) {
  owned_diagonal_pattern(3 * static_cast<std::size_t>(num_owned_), node_offset_, rows, cols);
}

bool LumpedInertiaForm::hessian(const double*, double* values) {
  if (device_) return device_->hessian(values);
  for (int i = 0; i < num_owned_; ++i)
    for (int c = 0; c < 3; ++c) values[3 * i + c] = mass_[i];
  return true;
}

ConsistentInertiaForm::ConsistentInertiaForm(const ElementData& elements, MemorySpace space) : elements_(elements) {
  if (space == MemorySpace::device) {  // the element masses live on the device only
    device_ = std::make_unique<DeviceConsistentInertiaPart>(elements);
    return;
  }
  x_hat_.assign(elements.reference.size(), 0.0);
  element_mass_.resize(64 * static_cast<std::size_t>(elements.num_elements()));
  for (int el = 0; el < elements.num_elements(); ++el) {
    double X[24];
    elements.gather_reference(el, X);
    hex8_consistent_mass(X, elements.rho[el], &element_mass_[64 * static_cast<std::size_t>(el)]);
  }
}

void ConsistentInertiaForm::begin_step(const double* x_hat) {
  if (device_) return device_->begin_step(x_hat);
  x_hat_.assign(x_hat, x_hat + elements_.reference.size());
}

bool ConsistentInertiaForm::value(const double* x, double* energy) {
  if (device_) return device_->value(x, energy);
  double e = 0;
  const std::int32_t* nodes = elements_.nodes.data();
  for (int el = 0; el < elements_.num_elements(); ++el) {
    const double* M = &element_mass_[64 * static_cast<std::size_t>(el)];
    const std::int32_t* n = nodes + 8 * static_cast<std::size_t>(el);
    for (int a = 0; a < 8; ++a)
      for (int b = 0; b < 8; ++b)
        for (int c = 0; c < 3; ++c)
          e += 0.5 * M[8 * a + b] * (x[3 * n[a] + c] - x_hat_[3 * n[a] + c]) * (x[3 * n[b] + c] - x_hat_[3 * n[b] + c]);
  }
  *energy = e;
  return true;
}

bool ConsistentInertiaForm::gradient(const double* x, double* g) {
  if (device_) return device_->gradient(x, g);
  const std::int32_t* nodes = elements_.nodes.data();
  for (int el = 0; el < elements_.num_elements(); ++el) {
    const double* M = &element_mass_[64 * static_cast<std::size_t>(el)];
    const std::int32_t* n = nodes + 8 * static_cast<std::size_t>(el);
    for (int a = 0; a < 8; ++a)
      for (int b = 0; b < 8; ++b)
        for (int c = 0; c < 3; ++c) g[3 * n[a] + c] += M[8 * a + b] * (x[3 * n[b] + c] - x_hat_[3 * n[b] + c]);
  }
  return true;
}

// Pattern: per element, the 8×8 scalar block expanded to the three components,
// entry (a, b, c) -> row 3·global(a)+c, col 3·global(b)+c, in the order a, b, c.
void ConsistentInertiaForm::coo_pattern(std::vector<PetscInt>* rows, std::vector<PetscInt>* cols) {
  elements_.consistent_mass_pattern(rows, cols);
}

bool ConsistentInertiaForm::hessian(const double* x, double* values) {
  return element_hessian(x, 0, elements_.num_elements(), values);
}

bool ConsistentInertiaForm::element_hessian(const double*, int first, int count, double* values) {
  if (device_) return device_->hessian(first, count, values);
  const std::size_t begin = 64 * static_cast<std::size_t>(first), end = begin + 64 * static_cast<std::size_t>(count);
  std::size_t k = 0;
  for (std::size_t m = begin; m < end; ++m)
    for (int c = 0; c < 3; ++c) values[k++] = element_mass_[m];
  return true;
}

}  // namespace dipc
