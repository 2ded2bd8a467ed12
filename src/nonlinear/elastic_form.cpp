#include "nonlinear/elastic_form.hpp"

#include <algorithm>

namespace dipc {

bool ElasticForm::value(const double* x, double* energy) {
  double psi = 0;
  const bool ok = elastic_energy(elements_.block(), x, &psi);
  *energy = scale_ * psi;
  return ok;
}

bool ElasticForm::gradient(const double* x, double* g) {
  gradient_work_.assign(elements_.reference.size(), 0.0);
  const bool ok = elastic_gradient(elements_.block(), x, gradient_work_.data());
  for (std::size_t i = 0; i < gradient_work_.size(); ++i) g[i] += scale_ * gradient_work_[i];
  return ok;
}

void ElasticForm::coo_pattern(std::vector<PetscInt>* rows, std::vector<PetscInt>* cols) {
  elements_.elastic_pattern(rows, cols);
}

bool ElasticForm::hessian(const double* x, double* values) {
  const bool ok = elastic_hessian(elements_.block(), x, values);
  const std::size_t n = 576 * static_cast<std::size_t>(elements_.num_elements());
  if (scale_ != 1.0) std::transform(values, values + n, values, [this](double v) { return scale_ * v; });
  return ok;
}

bool ElasticForm::is_valid(const double* x) {
  return min_volume_ratio(elements_.block(), x, nullptr) > 0.0;
}

}  // namespace dipc
