// Tests of the CPU element loops on a 2x2x2 block of distorted elements: COO patterns and
// values assembled densely against the element functions, the gradient loop against central
// differences of the energy loop, the fused loop, masses and volume ratios.
#include "assembly/element_loops.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <vector>

#include "physics/hex8_elasticity.hpp"
#include "physics/hex8_mass.hpp"
#include "physics/physics_test_support.hpp"

namespace dipc {
namespace {

// Structured 2x2x2 block: 27 nodes on a perturbed grid, local node ids shuffled so that
// neither local nor global numbering follows the grid, a random deformation, and
// per-element materials and densities.
struct Block {
  static constexpr int kNodes = 27;
  std::vector<std::int32_t> nodes;
  std::vector<double> reference, x, lambda, mu, rho;
  std::vector<std::int64_t> local_to_global;
  std::vector<MaterialModel> model;  // empty: all neo-Hookean
  ElementBlock view() const {
    ElementBlock b;
    b.num_elements = static_cast<int>(lambda.size());
    b.nodes = nodes.data();
    b.reference = reference.data();
    b.lambda = lambda.data();
    b.mu = mu.data();
    b.model = model.empty() ? nullptr : model.data();
    return b;
  }
  void element_coordinates(int e, const std::vector<double>& field, double out[24]) const {
    for (int a = 0; a < 8; ++a)
      for (int i = 0; i < 3; ++i) out[3 * a + i] = field[3 * nodes[8 * e + a] + i];
  }
};

Block make_block(std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<int> local_of_grid(Block::kNodes);
  std::iota(local_of_grid.begin(), local_of_grid.end(), 0);
  std::shuffle(local_of_grid.begin(), local_of_grid.end(), rng);
  Block b;
  b.reference.resize(3 * Block::kNodes);
  std::uniform_real_distribution<double> jitter(-0.08, 0.08);
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i) {
        const int n = local_of_grid[i + 3 * j + 9 * k];
        b.reference[3 * n] = i + jitter(rng);
        b.reference[3 * n + 1] = 1.5 * j + jitter(rng);
        b.reference[3 * n + 2] = 0.8 * k + jitter(rng);
      }
  for (int ek = 0; ek < 2; ++ek)
    for (int ej = 0; ej < 2; ++ej)
      for (int ei = 0; ei < 2; ++ei)
        for (int a = 0; a < 8; ++a) {
          const int i = ei + (hex8::corner_xi(a) > 0), j = ej + (hex8::corner_eta(a) > 0),
                    k = ek + (hex8::corner_zeta(a) > 0);
          b.nodes.push_back(local_of_grid[i + 3 * j + 9 * k]);
        }
  const test::Mat3 A = test::random_deformation_gradient(rng, 0.7, 0.25);
  std::uniform_real_distribution<double> noise(-0.05, 0.05);
  b.x.resize(3 * Block::kNodes);
  for (int n = 0; n < Block::kNodes; ++n)
    for (int i = 0; i < 3; ++i)
      b.x[3 * n + i] = A[3 * i] * b.reference[3 * n] + A[3 * i + 1] * b.reference[3 * n + 1] +
                       A[3 * i + 2] * b.reference[3 * n + 2] + noise(rng);
  for (int e = 0; e < 8; ++e) {
    double lambda, mu;
    lame_parameters(1e5 * (1 + e), 0.1 + 0.05 * e, &lambda, &mu);
    b.lambda.push_back(lambda);
    b.mu.push_back(mu);
    b.rho.push_back(1000.0 + 100 * e);
  }
  // Global ids: reversed local order, shifted as if other ranks owned lower ids.
  for (int n = 0; n < Block::kNodes; ++n) b.local_to_global.push_back(40 + (Block::kNodes - 1 - n));
  return b;
}

// Dense n x n sum of COO entries (duplicates add, as MatSetValuesCOO with ADD_VALUES).
std::vector<double> assemble_dense(const std::vector<std::int32_t>& rows, const std::vector<std::int32_t>& cols,
                                   const std::vector<double>& values, int n) {
  std::vector<double> A(static_cast<std::size_t>(n) * n, 0.0);
  for (std::size_t k = 0; k < values.size(); ++k) A[static_cast<std::size_t>(n) * rows[k] + cols[k]] += values[k];
  return A;
}

constexpr int kGlobalDofs = 3 * (40 + Block::kNodes);

TEST(ElementLoops, EnergyLoopSumsElementEnergies) {
  const Block b = make_block(41);
  double total = 0;
  for (int e = 0; e < 8; ++e) {
    double Xe[24], xe[24], ee;
    b.element_coordinates(e, b.reference, Xe);
    b.element_coordinates(e, b.x, xe);
    ASSERT_TRUE(hex8_neo_hookean(Xe, xe, b.lambda[e], b.mu[e], &ee, nullptr, nullptr));
    total += ee;
  }
  double energy = -1;
  ASSERT_TRUE(elastic_energy(b.view(), b.x.data(), &energy));
  EXPECT_NEAR(energy, total, 1e-13 * std::abs(total));
  EXPECT_GT(energy, 0.0);
}

TEST(ElementLoops, GradientLoopIsCentralDifferenceOfEnergyLoop) {
  const Block b = make_block(42);
  std::vector<double> g(b.x.size(), 0.0);
  ASSERT_TRUE(elastic_gradient(b.view(), b.x.data(), g.data()));
  const double h = 1e-6;
  const int n = static_cast<int>(g.size());
  std::vector<double> g_fd(b.x.size());
  const auto energy = [&](const double* x, double* e) { return elastic_energy(b.view(), x, e); };
  ASSERT_TRUE(test::central_difference(energy, b.x.data(), n, 1, h, g_fd.data()));
  EXPECT_LT(test::max_abs_difference(g.data(), g_fd.data(), n), 1e-6 * test::max_abs(g.data(), n));
}

TEST(ElementLoops, HessianCooAssemblesToSumOfElementHessians) {
  const Block b = make_block(43);
  const ElementBlock view = b.view();
  std::vector<std::int32_t> rows, cols;
  elastic_coo_pattern(view, b.local_to_global.data(), &rows, &cols);
  ASSERT_EQ(rows.size(), 8u * kElasticCooPerElement);
  ASSERT_EQ(cols.size(), rows.size());
  std::vector<double> values(rows.size());
  ASSERT_TRUE(elastic_hessian(view, b.x.data(), values.data()));
  const auto assembled = assemble_dense(rows, cols, values, kGlobalDofs);

  // Reference: scatter every element's 24x24 Hessian by hand through the global ids.
  std::vector<double> expected(static_cast<std::size_t>(kGlobalDofs) * kGlobalDofs, 0.0);
  for (int e = 0; e < 8; ++e) {
    double Xe[24], xe[24], He[576];
    b.element_coordinates(e, b.reference, Xe);
    b.element_coordinates(e, b.x, xe);
    ASSERT_TRUE(hex8_neo_hookean(Xe, xe, b.lambda[e], b.mu[e], nullptr, nullptr, He));
    for (int a = 0; a < 8; ++a)
      for (int i = 0; i < 3; ++i)
        for (int c = 0; c < 8; ++c)
          for (int j = 0; j < 3; ++j) {
            const std::int64_t r = 3 * b.local_to_global[b.nodes[8 * e + a]] + i;
            const std::int64_t s = 3 * b.local_to_global[b.nodes[8 * e + c]] + j;
            expected[kGlobalDofs * r + s] += He[24 * (3 * a + i) + 3 * c + j];
          }
  }
  const int n2 = kGlobalDofs * kGlobalDofs;
  EXPECT_LT(test::max_abs_difference(assembled.data(), expected.data(), n2),
            1e-12 * test::max_abs(expected.data(), n2));
  // Rows of the 40 leading global nodes (owned by "other ranks") receive nothing.
  EXPECT_EQ(test::max_abs(assembled.data(), 3 * 40 * kGlobalDofs), 0.0);
}

TEST(ElementLoops, FusedLoopEqualsSeparateLoops) {
  const Block b = make_block(44);
  const ElementBlock view = b.view();
  double energy, fused_energy;
  std::vector<double> g(b.x.size(), 0.5);  // both loops add into the same non-zero start
  std::vector<double> fused_g = g;
  std::vector<double> H(8 * kElasticCooPerElement, 0.0);
  std::vector<double> fused_H = H;
  ASSERT_TRUE(elastic_energy(view, b.x.data(), &energy));
  ASSERT_TRUE(elastic_gradient(view, b.x.data(), g.data()));
  ASSERT_TRUE(elastic_hessian(view, b.x.data(), H.data()));
  ASSERT_TRUE(elastic_energy_gradient_hessian(view, b.x.data(), &fused_energy, fused_g.data(), fused_H.data()));
  EXPECT_EQ(fused_energy, energy);
  EXPECT_EQ(test::max_abs_difference(fused_g.data(), g.data(), static_cast<int>(g.size())), 0.0);
  EXPECT_EQ(test::max_abs_difference(fused_H.data(), H.data(), static_cast<int>(H.size())), 0.0);
}

// Every other element stable neo-Hookean: each loop evaluates each element with its own
// material (element energies and COO values against the element routines), and the gradient
// loop is still the derivative of the energy loop.
TEST(ElementLoops, MixedMaterialsUseEachElementsOwn) {
  Block b = make_block(46);
  for (int e = 0; e < 8; ++e) b.model.push_back(e % 2 ? MaterialModel::stable_neo_hookean : MaterialModel::neo_hookean);
  const ElementBlock view = b.view();
  double total = 0, total_nh = 0;
  std::vector<double> expected_H(8 * kElasticCooPerElement);
  for (int e = 0; e < 8; ++e) {
    double Xe[24], xe[24], ee, ee_nh, He[576];
    b.element_coordinates(e, b.reference, Xe);
    b.element_coordinates(e, b.x, xe);
    if (e % 2)
      ASSERT_TRUE(hex8_element<StableNeoHookean>(Xe, xe, b.lambda[e], b.mu[e], &ee, nullptr, He));
    else
      ASSERT_TRUE(hex8_element<NeoHookean>(Xe, xe, b.lambda[e], b.mu[e], &ee, nullptr, He));
    ASSERT_TRUE(hex8_neo_hookean(Xe, xe, b.lambda[e], b.mu[e], &ee_nh, nullptr, nullptr));
    total += ee;
    total_nh += ee_nh;
    for (int a = 0; a < 8; ++a)
      for (int k = 0; k < 3; ++k)
        for (int c = 0; c < 8; ++c)
          for (int l = 0; l < 3; ++l)
            expected_H[kElasticCooPerElement * e + elastic_coo_offset(a, k, c, l)] = He[24 * (3 * a + k) + 3 * c + l];
  }
  double energy = -1;
  ASSERT_TRUE(elastic_energy(view, b.x.data(), &energy));
  EXPECT_NEAR(energy, total, 1e-13 * std::abs(total));
  EXPECT_GT(std::abs(energy - total_nh), 1e-6 * std::abs(total_nh)) << "the materials must differ at this strain";
  std::vector<double> H(expected_H.size()), H_split(expected_H.size()), b_split(24 * 8), d_split(8);
  ASSERT_TRUE(elastic_hessian(view, b.x.data(), H.data()));
  const int n = static_cast<int>(H.size());
  EXPECT_LT(test::max_abs_difference(H.data(), expected_H.data(), n), 1e-12 * test::max_abs(expected_H.data(), n));
  ASSERT_TRUE(elastic_hessian_split(view, b.x.data(), H_split.data(), b_split.data(), d_split.data()));
  EXPECT_EQ(test::max_abs_difference(H_split.data(), H.data(), n), 0.0);
  EXPECT_EQ(test::max_abs(d_split.data(), 8), 0.0);

  std::vector<double> g(b.x.size(), 0.0), g_fd(b.x.size());
  ASSERT_TRUE(elastic_gradient(view, b.x.data(), g.data()));
  const double h = 1e-6;
  for (std::size_t k = 0; k < b.x.size(); ++k) {
    std::vector<double> xp = b.x, xm = b.x;
    xp[k] += h;
    xm[k] -= h;
    double ep, em;
    ASSERT_TRUE(elastic_energy(view, xp.data(), &ep));
    ASSERT_TRUE(elastic_energy(view, xm.data(), &em));
    g_fd[k] = (ep - em) / (2 * h);
  }
  const int ng = static_cast<int>(g.size());
  EXPECT_LT(test::max_abs_difference(g.data(), g_fd.data(), ng), 1e-6 * test::max_abs(g.data(), ng));
}

TEST(ElementLoops, InvertedElementFailsEveryElasticLoop) {
  Block b = make_block(45);
  // Push the block's centre node (shared by all 8 elements) far outside: elements invert.
  int centre = -1;
  for (int n = 0; n < Block::kNodes; ++n) {
    int count = 0;
    for (std::int32_t id : b.nodes) count += id == n;
    if (count == 8) centre = n;
  }
  ASSERT_GE(centre, 0);
  b.x[3 * centre] += 5.0;
  const ElementBlock view = b.view();
  double energy;
  std::vector<double> g(b.x.size(), 0.0), H(8 * kElasticCooPerElement);
  EXPECT_FALSE(elastic_energy(view, b.x.data(), &energy));
  EXPECT_FALSE(elastic_gradient(view, b.x.data(), g.data()));
  EXPECT_FALSE(elastic_hessian(view, b.x.data(), H.data()));
  EXPECT_FALSE(elastic_energy_gradient_hessian(view, b.x.data(), &energy, g.data(), H.data()));
  EXPECT_LT(min_volume_ratio(view, b.x.data(), nullptr), 0.0);
}

TEST(ElementLoops, MinVolumeRatioIsMinimumOverElements) {
  const Block b = make_block(46);
  std::vector<double> per_element(8);
  const double m = min_volume_ratio(b.view(), b.x.data(), per_element.data());
  double expected = 1e300;
  for (int e = 0; e < 8; ++e) {
    double Xe[24], xe[24];
    b.element_coordinates(e, b.reference, Xe);
    b.element_coordinates(e, b.x, xe);
    EXPECT_EQ(per_element[e], hex8_min_volume_ratio(Xe, xe));
    expected = std::min(expected, per_element[e]);
  }
  EXPECT_EQ(m, expected);
  EXPECT_GT(m, 0.0);
}

TEST(ElementLoops, MassLoopsAssembleConsistentAndLumpedMass) {
  const Block b = make_block(47);
  const ElementBlock view = b.view();
  std::vector<std::int32_t> rows, cols;
  consistent_mass_coo_pattern(view, b.local_to_global.data(), &rows, &cols);
  ASSERT_EQ(rows.size(), 8u * kMassCooPerElement);
  std::vector<double> values(rows.size());
  consistent_mass_values(view, b.rho.data(), values.data());
  const auto M = assemble_dense(rows, cols, values, kGlobalDofs);

  // Reference: M_ab (x) I_3 scattered by hand.
  std::vector<double> expected(static_cast<std::size_t>(kGlobalDofs) * kGlobalDofs, 0.0);
  double total_mass = 0;
  for (int e = 0; e < 8; ++e) {
    double Xe[24], Me[64], me[8];
    b.element_coordinates(e, b.reference, Xe);
    hex8_consistent_mass(Xe, b.rho[e], Me);
    hex8_lumped_mass(Xe, b.rho[e], me);
    for (int a = 0; a < 8; ++a) {
      total_mass += me[a];
      for (int c = 0; c < 8; ++c)
        for (int k = 0; k < 3; ++k) {
          const std::int64_t r = 3 * b.local_to_global[b.nodes[8 * e + a]] + k;
          const std::int64_t s = 3 * b.local_to_global[b.nodes[8 * e + c]] + k;
          expected[kGlobalDofs * r + s] += Me[8 * a + c];
        }
    }
  }
  const int n2 = kGlobalDofs * kGlobalDofs;
  EXPECT_LT(test::max_abs_difference(M.data(), expected.data(), n2), 1e-13 * test::max_abs(expected.data(), n2));

  // Lumped loop = row sums of the assembled consistent mass (one component), total = sum rho V.
  std::vector<double> lumped(Block::kNodes, 0.0);
  lumped_mass(view, b.rho.data(), lumped.data());
  double lumped_total = 0;
  for (int n = 0; n < Block::kNodes; ++n) {
    const std::int64_t r = 3 * b.local_to_global[n] + 1;
    double row = 0;
    for (int s = 0; s < kGlobalDofs; ++s) row += M[kGlobalDofs * r + s];
    EXPECT_NEAR(lumped[n], row, 1e-12 * row);
    lumped_total += lumped[n];
  }
  EXPECT_NEAR(lumped_total, total_mass, 1e-12 * total_mass);
}

TEST(ElementLoops, PatternRejectsDofIdsBeyondInt32) {
  Block b = make_block(48);
  b.local_to_global[5] = (std::int64_t{1} << 31) / 3;  // 3*id + 2 > 2^31 - 1
  std::vector<std::int32_t> rows, cols;
  EXPECT_THROW(elastic_coo_pattern(b.view(), b.local_to_global.data(), &rows, &cols), DofIndexOverflow);
  EXPECT_THROW(consistent_mass_coo_pattern(b.view(), b.local_to_global.data(), &rows, &cols), DofIndexOverflow);
  b.local_to_global[5] = (std::int64_t{1} << 31) / 3 - 1;
  EXPECT_NO_THROW(elastic_coo_pattern(b.view(), b.local_to_global.data(), &rows, &cols));
}

}  // namespace
}  // namespace dipc
