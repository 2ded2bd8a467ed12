#include "forms/elastic_form.hpp"

#include <algorithm>
#include <limits>
#include <vector>

#include "threads/host_threads.hpp"

namespace dipc {

ElasticForm::ElasticForm(const ElementData& elements, double scale, MemorySpace space)
    : elements_(elements), scale_(scale) {
  if (space == MemorySpace::device) device_ = std::make_unique<DeviceElasticPart>(elements);
  for (int e = 0; e < elements.num_elements(); ++e)
    if (elements.volumetric[e] == VolumetricTerm::mean_dilatation) split_elements_.push_back(e);
}

double ElasticForm::split_stiffness_ratio() const {
  double ratio = 0;
  for (int e : split_elements_) ratio = std::max(ratio, elements_.lambda[e] / elements_.mu[e]);
  return ratio;
}

void ElasticForm::split_volumetric() {
  if (split_ || split_elements_.empty()) return;
  split_ = true;
  const std::size_t rows = split_elements_.size();
  part_.rows = static_cast<int>(rows);
  part_.local_dofs.resize(24 * rows);
  part_.global_dofs.resize(24 * rows);
  part_.gradient.assign(24 * rows, 0.0);
  part_.curvature.assign(rows, 0.0);
  part_.weight.assign(rows, 0.0);
  std::vector<double> all_volumes(elements_.num_elements());
  reference_volumes(elements_.block(), all_volumes.data());
  volumes_.resize(rows);
  for (std::size_t r = 0; r < rows; ++r) {
    const int e = split_elements_[r];
    volumes_[r] = all_volumes[e];
    for (int a = 0; a < 8; ++a) {
      const std::int32_t node = elements_.nodes[8 * static_cast<std::size_t>(e) + a];
      for (int c = 0; c < 3; ++c) {
        part_.local_dofs[24 * r + 3 * a + c] = 3 * node + c;
        part_.global_dofs[24 * r + 3 * a + c] = static_cast<PetscInt>(3 * elements_.local_to_global[node] + c);
      }
    }
  }
}

bool ElasticForm::value(const double* x, double* energy) {
  if (device_) return device_->value(x, scale_, energy);
  double psi = 0;
  const bool ok = elastic_energy(elements_.block(), x, &psi);
  *energy = scale_ * psi;
  return ok;
}

bool ElasticForm::gradient(const double* x, double* g) {
  if (device_) return device_->gradient(x, scale_, g);
  gradient_work_.assign(elements_.reference.size(), 0.0);
  const bool ok = elastic_gradient(elements_.block(), x, gradient_work_.data());
  for (std::size_t i = 0; i < gradient_work_.size(); ++i) g[i] += scale_ * gradient_work_[i];
  return ok;
}

void ElasticForm::coo_pattern(std::vector<PetscInt>* rows, std::vector<PetscInt>* cols) {
  elements_.elastic_pattern(rows, cols);
}

bool ElasticForm::hessian(const double* x, double* values) {
  return element_hessian(x, 0, elements_.num_elements(), values);
}

bool ElasticForm::element_hessian(const double* x, int first, int count, double* values) {
  if (device_) return device_->hessian(x, scale_, first, count, values);
  const ElementBlock range = element_range(elements_.block(), first, count);
  bool ok;
  if (split_) {
    const std::size_t ne = static_cast<std::size_t>(elements_.num_elements());
    b_work_.resize(24 * ne);
    f2_work_.resize(ne);
    ok = elastic_hessian_split(range, x, values, b_work_.data() + 24 * static_cast<std::size_t>(first),
                               f2_work_.data() + first);
    // The split elements of this range (split_elements_ ascends).
    const auto begin = std::lower_bound(split_elements_.begin(), split_elements_.end(), first);
    const auto end = std::lower_bound(begin, split_elements_.end(), first + count);
    for (auto it = begin; it != end; ++it) {
      const std::size_t r = static_cast<std::size_t>(it - split_elements_.begin());
      const std::size_t e = static_cast<std::size_t>(*it);
      std::copy(b_work_.begin() + 24 * e, b_work_.begin() + 24 * e + 24, part_.gradient.begin() + 24 * r);
      part_.curvature[r] = scale_ * f2_work_[e];
      part_.weight[r] = volumes_[r] / (scale_ * elements_.mu[e]);
    }
  } else {
    ok = elastic_hessian(range, x, values);
  }
  const std::size_t n = kElasticCooPerElement * static_cast<std::size_t>(count);
  if (scale_ != 1.0) std::transform(values, values + n, values, [this](double v) { return scale_ * v; });
  return ok;
}

bool ElasticForm::is_valid(const double* x) {
  if (device_) return device_->is_valid(x);
  double ratio = 0;
  min_volume_ratio(x, &ratio);
  return ratio > 0.0;
}

bool ElasticForm::min_volume_ratio(const double* x, double* ratio) {
  if (device_) {
    *ratio = device_->min_volume_ratio(x);
    return true;
  }
  // On the host threads, each over a range of elements; a minimum does not depend on the split.
  const ElementBlock& block = elements_.block();
  std::vector<double> chunk_min(static_cast<std::size_t>(host_threads()), std::numeric_limits<double>::max());
  parallel_chunks(static_cast<std::size_t>(block.num_elements), [&](int c, std::size_t begin, std::size_t end) {
    const ElementBlock range = element_range(block, static_cast<int>(begin), static_cast<int>(end - begin));
    chunk_min[static_cast<std::size_t>(c)] = dipc::min_volume_ratio(range, x, nullptr);
  });
  *ratio = *std::min_element(chunk_min.begin(), chunk_min.end());
  return true;
}

}  // namespace dipc
