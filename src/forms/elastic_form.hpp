// ElasticForm: scale · Ψ(x), Ψ the neo-Hookean strain energy of this rank's hex8 elements
// (docs/design.md §1.2); scale = h² in implicit Euler, 1 in a static solve. With mean-dilatation
// elements it can hand their volumetric terms to the mixed u-p solve (VolumetricSplit).
#pragma once
#include <memory>

#include "forms/device_form_parts.hpp"
#include "forms/element_data.hpp"
#include "forms/form.hpp"
#include "forms/volumetric_split.hpp"

namespace dipc {

class ElasticForm : public Form, public VolumetricSplit {
 public:
  // space: where value, gradient, hessian and is_valid run (device: through a
  // DeviceElasticPart, device_form_parts.hpp).
  ElasticForm(const ElementData& elements, double scale, MemorySpace space = MemorySpace::host);
  std::string name() const override { return "elastic"; }
  MemorySpace memory_space() const override { return device_ ? MemorySpace::device : MemorySpace::host; }
  bool value(const double* x, double* energy) override;
  bool gradient(const double* x, double* g) override;
  void coo_pattern(std::vector<PetscInt>* rows, std::vector<PetscInt>* cols) override;
  bool hessian(const double* x, double* values) override;
  bool element_pattern(ElementPattern* pattern) const override {
    *pattern = elements_.pattern(ElementLayout::elastic);
    return true;
  }
  bool element_hessian(const double* x, int first, int count, double* values) override;
  bool is_valid(const double* x) override;
  bool min_volume_ratio(const double* x, double* ratio) override;
  void set_time_step(double h) override { scale_ = h * h; }
  // This form when some element is a mean-dilatation one (its rank-one volumetric term can be
  // split); only on the host: the device part does not hand over B and D.
  VolumetricSplit* volumetric_split() override { return !device_ && !split_elements_.empty() ? this : nullptr; }
  double split_stiffness_ratio() const override;
  void split_volumetric() override;
  const VolumetricPart* volumetric_part() const override { return split_ ? &part_ : nullptr; }

 private:
  const ElementData& elements_;
  double scale_;
  std::unique_ptr<DeviceElasticPart> device_;  // device space only
  std::vector<double> gradient_work_;
  std::vector<int> split_elements_;  // the mean-dilatation elements, one volumetric row each
  bool split_ = false;
  VolumetricPart part_;
  std::vector<double> volumes_;           // reference volume per split element
  std::vector<double> b_work_, f2_work_;  // per element of the block
};

}  // namespace dipc
