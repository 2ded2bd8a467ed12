// ElasticForm: scale · Ψ(x), Ψ the neo-Hookean strain energy of this rank's hex8 elements
// (DESIGN.md §1); scale = h² in implicit Euler, 1 in a static solve.
#pragma once
#include "nonlinear/element_data.hpp"
#include "nonlinear/form.hpp"

namespace dipc {

class ElasticForm : public Form {
 public:
  ElasticForm(const ElementData& elements, double scale) : elements_(elements), scale_(scale) {}
  std::string name() const override { return "elastic"; }
  bool value(const double* x, double* energy) override;
  bool gradient(const double* x, double* g) override;
  void coo_pattern(std::vector<PetscInt>* rows, std::vector<PetscInt>* cols) override;
  bool hessian(const double* x, double* values) override;
  bool is_valid(const double* x) override;
  void set_time_step(double h) override { scale_ = h * h; }

 private:
  const ElementData& elements_;
  double scale_;
  std::vector<double> gradient_work_;
};

}  // namespace dipc
