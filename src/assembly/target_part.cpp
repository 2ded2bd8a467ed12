#include "assembly/target_part.hpp"

#include <atomic>
#include <limits>
#include <stdexcept>

#include "threads/host_threads.hpp"

namespace dipc {

std::size_t TargetPart::build(const PetscInt* rows, const PetscInt* cols, std::size_t n, const CooPart::Find& find) {
  // The device sort counts its items in int.
  if (n > static_cast<std::size_t>(std::numeric_limits<int>::max()))
    throw std::length_error("more than 2^31 - 1 changing Hessian entries on one rank: run on more ranks");
  num_raw_ = n;
  target_.assign(n, kDropped);
  std::vector<std::size_t> chunk_missing(static_cast<std::size_t>(host_threads()), 0);
  std::atomic<bool> too_far{false};
  const int chunks = parallel_chunks(n, [&](int c, std::size_t k0, std::size_t k1) {
    std::size_t row_hint = 0, missing = 0;
    for (std::size_t k = k0; k < k1; ++k) {
      if (rows[k] < 0 || cols[k] < 0) continue;
      const std::int64_t t = find(rows[k], cols[k], &row_hint);
      if (t < 0) {
        ++missing;
      } else if (static_cast<std::uint64_t>(t) >= kDropped) {
        too_far = true;
      } else {
        target_[k] = static_cast<std::uint32_t>(t);
      }
    }
    chunk_missing[static_cast<std::size_t>(c)] = missing;
  });
  if (too_far) throw std::length_error("more than 2^32 - 2 Hessian entries on one rank: run on more ranks");
  std::size_t missing = 0;
  for (int c = 0; c < chunks; ++c) missing += chunk_missing[static_cast<std::size_t>(c)];
  return missing;
}

void TargetPart::keep_on_device() {
  d_keys_.upload(target_);
  d_sources_.resize(num_raw_);
  device::sort_by_target(d_keys_.data(), d_sources_.data(), num_raw_);
  std::vector<std::uint32_t>().swap(target_);
}

void TargetPart::add(const double* raw, double* unique) const {
  for (std::size_t k = 0; k < num_raw_; ++k)
    if (target_[k] != kDropped) unique[target_[k]] += raw[k];
}

void TargetPart::add_on_device(const double* d_raw, double* d_unique) const {
  device::add_by_target(d_unique, d_keys_.data(), d_sources_.data(), d_raw, num_raw_);
}

}  // namespace dipc
