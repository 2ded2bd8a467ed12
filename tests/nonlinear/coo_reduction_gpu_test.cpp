// device::reduce_coo against CooReduction::reduce on a random element-like pattern: the same
// sums in the same order, so the same bits. Skips where no GPU is present.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include "device/device_runtime.hpp"
#include "nonlinear/coo_reduction.hpp"

namespace dipc {
namespace {

TEST(CooReductionGpu, DeviceSumsEqualHostSumsBitForBit) {
  if (device::device_count() == 0) GTEST_SKIP() << "no CUDA device";
  std::mt19937_64 rng(11);
  const PetscInt owned_begin = 3000, owned_end = 9000;
  std::uniform_int_distribution<PetscInt> owned(owned_begin, owned_end - 1), any(0, 12000);
  std::uniform_int_distribution<int> pick(0, 19);
  std::vector<PetscInt> rows, cols;
  for (int block = 0; block < 3000; ++block) {
    PetscInt dofs[24];
    for (PetscInt& d : dofs) d = pick(rng) == 0 ? any(rng) : owned(rng);
    for (PetscInt r : dofs)
      for (PetscInt c : dofs) rows.push_back(r), cols.push_back(pick(rng) == 0 && pick(rng) == 0 ? -1 : c);
  }
  const CooReduction reduction =
      CooReduction::build(rows.data(), cols.data(), rows.size(), owned_begin, owned_end);
  // Values over many magnitudes, so that a different summation order would change the bits.
  std::uniform_real_distribution<double> mantissa(-1, 1), exponent(-12, 12);
  std::vector<double> raw(rows.size());
  for (double& v : raw) v = mantissa(rng) * std::pow(10.0, exponent(rng));
  std::vector<double> host(reduction.num_unique());
  reduction.reduce(raw.data(), host.data());

  device::Array<double> d_raw("raw"), d_unique("unique");
  device::Array<CooReduction::Index> d_offsets("offsets"), d_sources("sources");
  d_raw.upload(raw);
  d_offsets.upload(reduction.offsets);
  d_sources.upload(reduction.sources);
  d_unique.resize(reduction.num_unique());
  device::reduce_coo(d_raw.data(), d_offsets.data(), d_sources.data(), reduction.num_unique(), d_unique.data());
  const std::vector<double> device_sums = d_unique.to_host();
  ASSERT_EQ(device_sums.size(), host.size());
  ASSERT_GT(host.size(), 0u);
  EXPECT_EQ(std::memcmp(device_sums.data(), host.data(), host.size() * sizeof(double)), 0);
  for (std::size_t u = 0; u < host.size(); ++u) ASSERT_EQ(device_sums[u], host[u]) << "unique entry " << u;
}

}  // namespace
}  // namespace dipc
