#include "nonlinear/body_force_form.hpp"

namespace dipc {

BodyForceForm::BodyForceForm(const std::vector<double>& node_mass, int num_owned_nodes,
                             const std::array<double, 3>& acceleration, double scale)
    : force_(3 * static_cast<std::size_t>(num_owned_nodes)) {
  for (int i = 0; i < num_owned_nodes; ++i)
    for (int c = 0; c < 3; ++c) force_[3 * i + c] = scale * node_mass[i] * acceleration[c];
}

bool BodyForceForm::value(const double* x, double* energy) {
  double e = 0;
  for (std::size_t k = 0; k < force_.size(); ++k) e -= force_[k] * x[k];
  *energy = e;
  return true;
}

bool BodyForceForm::gradient(const double*, double* g) {
  for (std::size_t k = 0; k < force_.size(); ++k) g[k] -= force_[k];
  return true;
}

void BodyForceForm::coo_pattern(std::vector<PetscInt>* rows, std::vector<PetscInt>* cols) {
  rows->clear();
  cols->clear();
}

}  // namespace dipc
