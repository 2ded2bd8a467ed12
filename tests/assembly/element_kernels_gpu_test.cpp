// CUDA element kernels against the CPU element loops on random valid states of a distorted
// box mesh with neo-Hookean, mean-dilatation and stable neo-Hookean elements (alone and mixed
// in one block): energy, gradient, PSD Hessian COO values, minimum volume ratio, and the inertia
// and body-force terms, to 1e-12 relative to the largest entry. Skips where no GPU is present;
// runs on the lent GPU machine.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "assembly/cuda/element_kernels.hpp"
#include "assembly/element_loops.hpp"
#include "device/device_runtime.hpp"
#include "physics/hex8_mass.hpp"

namespace dipc {
namespace {

// n×n×n unit-spaced hexes, nodes jittered in the reference and x = random deformation of it.
struct RandomBlock {
  std::vector<std::int32_t> nodes;
  std::vector<double> reference, x, lambda, mu, rho;
  std::vector<VolumetricTerm> volumetric;  // empty: all standard
  std::vector<MaterialModel> model;        // empty: all neo-Hookean
  ElementBlock block() const {
    ElementBlock b;
    b.num_elements = static_cast<int>(lambda.size());
    b.nodes = nodes.data(), b.reference = reference.data(), b.lambda = lambda.data(), b.mu = mu.data();
    b.volumetric = volumetric.empty() ? nullptr : volumetric.data();
    b.model = model.empty() ? nullptr : model.data();
    return b;
  }
};

RandomBlock random_block(int n, unsigned seed, double strain) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> jitter(-0.15, 0.15), u(-1, 1), E(1e4, 1e8), nu(0.0, 0.49);
  RandomBlock b;
  const int m = n + 1;
  auto id = [m](int i, int j, int k) { return (k * m + j) * m + i; };
  for (int k = 0; k < m; ++k)
    for (int j = 0; j < m; ++j)
      for (int i = 0; i < m; ++i)
        for (double c : {double(i), double(j), double(k)}) b.reference.push_back(c + jitter(rng));
  // A smooth random deformation x = X + strain (A X + sin terms): valid for small strain.
  double A[9];
  for (double& a : A) a = u(rng);
  b.x.resize(b.reference.size());
  for (std::size_t p = 0; p < b.reference.size() / 3; ++p)
    for (int i = 0; i < 3; ++i) {
      const double* X = &b.reference[3 * p];
      b.x[3 * p + i] = X[i] + strain * (A[3 * i] * X[0] + A[3 * i + 1] * X[1] + A[3 * i + 2] * X[2] +
                                        std::sin(X[(i + 1) % 3] + seed));
    }
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const int c[8] = {id(i, j, k),     id(i + 1, j, k),     id(i + 1, j + 1, k),     id(i, j + 1, k),
                          id(i, j, k + 1), id(i + 1, j, k + 1), id(i + 1, j + 1, k + 1), id(i, j + 1, k + 1)};
        b.nodes.insert(b.nodes.end(), c, c + 8);
        const double e = E(rng), v = nu(rng);
        b.lambda.push_back(e * v / ((1 + v) * (1 - 2 * v)));
        b.mu.push_back(e / (2 * (1 + v)));
        b.rho.push_back(1000);
      }
  return b;
}

// Device copies of a block, freed with it.
struct DeviceBlock {
  device::Array<std::int32_t> nodes;
  device::Array<double> reference, lambda, mu;
  device::Array<VolumetricTerm> volumetric;
  device::Array<MaterialModel> model;
  explicit DeviceBlock(const RandomBlock& b) {
    nodes.upload(b.nodes), reference.upload(b.reference), lambda.upload(b.lambda), mu.upload(b.mu);
    volumetric.upload(b.volumetric);
    model.upload(b.model);
  }
  ElementBlock block(int n) const {
    ElementBlock d;
    d.num_elements = n;
    d.nodes = nodes.data(), d.reference = reference.data(), d.lambda = lambda.data(), d.mu = mu.data();
    d.volumetric = volumetric.size() ? volumetric.data() : nullptr;
    d.model = model.size() ? model.data() : nullptr;
    return d;
  }
};

double max_relative_difference(const std::vector<double>& a, const std::vector<double>& b) {
  double diff = 0, scale = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    diff = std::max(diff, std::abs(a[i] - b[i]));
    scale = std::max(scale, std::abs(a[i]));
  }
  return diff / scale;
}

class ElementKernelsGpu : public ::testing::Test {
 protected:
  void SetUp() override {
    if (device::device_count() == 0) GTEST_SKIP() << "no CUDA device";
  }
};

// The element kinds and materials of a test block: all standard neo-Hookean (the plain
// kernel); every other element mean-dilatation with nu up to 0.4999; all stable neo-Hookean
// (the per-element material variant); and a mix of the three in one block (both variants).
enum class Mix { neo_hookean, mean_dilatation, stable_neo_hookean, all };

void assign_kinds(Mix mix, RandomBlock* b) {
  for (std::size_t e = 0; e < b->lambda.size(); ++e) {
    const bool md = (mix == Mix::mean_dilatation && e % 2) || (mix == Mix::all && e % 3 == 1);
    const bool snh = mix == Mix::stable_neo_hookean || (mix == Mix::all && e % 3 == 2);
    if (mix == Mix::mean_dilatation || mix == Mix::all)
      b->volumetric.push_back(md ? VolumetricTerm::mean_dilatation : VolumetricTerm::gauss_points);
    if (mix == Mix::stable_neo_hookean || mix == Mix::all)
      b->model.push_back(snh ? MaterialModel::stable_neo_hookean : MaterialModel::neo_hookean);
    if (e % 4 == 1) b->lambda[e] = 4999 * b->mu[e];  // nu = 0.4999: lambda = 2 mu nu / (1 - 2 nu)
  }
}

TEST_F(ElementKernelsGpu, ElasticValueGradientHessianMatchTheCpu) {
  for (Mix mix : {Mix::neo_hookean, Mix::mean_dilatation, Mix::stable_neo_hookean, Mix::all})
    for (unsigned seed : {1u, 2u, 3u}) {
      for (double strain : {0.0, 0.05, 0.3}) {
        RandomBlock b = random_block(9, seed, strain);
        const int mixed = static_cast<int>(mix);
        if (mix != Mix::neo_hookean) assign_kinds(mix, &b);
        const ElementBlock hb = b.block();
        ASSERT_GT(min_volume_ratio(hb, b.x.data(), nullptr), 0.0) << "test state must be valid";
        double e_cpu = 0;
        std::vector<double> g_cpu(b.x.size(), 0.0), H_cpu(kElasticCooPerElement * hb.num_elements);
        ASSERT_TRUE(elastic_energy_gradient_hessian(hb, b.x.data(), &e_cpu, g_cpu.data(), H_cpu.data()));

        DeviceBlock d(b);
        device::Array<double> x, g, H;
        x.upload(b.x);
        g.resize(b.x.size());
        g.set_zero();
        H.resize(H_cpu.size());
        device::Reducer reducer;
        double e_gpu = 0;
        const double scale = 0.25;  // as h² scales the elastic form
        ASSERT_TRUE(
            device::elastic_evaluate(d.block(hb.num_elements), x.data(), scale, &e_gpu, g.data(), H.data(), reducer));
        std::vector<double> g_gpu = g.to_host(), H_gpu = H.to_host();
        for (double& v : g_gpu) v /= scale;
        for (double& v : H_gpu) v /= scale;
        // At rest (strain 0) energy and gradient vanish up to rounding, so they are compared on the
        // scales that rounding acts on: Σ μ_e for the energy (unit volumes), max |H| for g.
        double mu_sum = 0, H_max = 0;
        for (double m : b.mu) mu_sum += m;
        for (double h : H_cpu) H_max = std::max(H_max, std::abs(h));
        const double e_scale = std::max(std::abs(e_cpu), mu_sum);
        double g_diff = 0, g_max = 0;
        for (std::size_t i = 0; i < g_cpu.size(); ++i) {
          g_diff = std::max(g_diff, std::abs(g_cpu[i] - g_gpu[i]));
          g_max = std::max(g_max, std::abs(g_cpu[i]));
        }
        EXPECT_LE(std::abs(e_gpu / scale - e_cpu), 1e-12 * e_scale) << mixed << " " << seed << " " << strain;
        EXPECT_LE(g_diff, 1e-12 * std::max(g_max, H_max)) << mixed << " " << seed << " " << strain;
        EXPECT_LE(max_relative_difference(H_cpu, H_gpu), 1e-12) << mixed << " " << seed << " " << strain;

        // Each output alone (the line search asks for the energy only).
        double e_only = 0;
        ASSERT_TRUE(
            device::elastic_evaluate(d.block(hb.num_elements), x.data(), 1.0, &e_only, nullptr, nullptr, reducer));
        EXPECT_LE(std::abs(e_only - e_cpu), 1e-12 * e_scale);
        const double r_cpu = min_volume_ratio(hb, b.x.data(), nullptr);
        EXPECT_DOUBLE_EQ(device::min_volume_ratio(d.block(hb.num_elements), x.data(), reducer), r_cpu);
      }
    }
}

// Also for stable neo-Hookean, whose energy is finite there: dipc refuses inverted elements.
TEST_F(ElementKernelsGpu, InvertedElementIsReported) {
  for (Mix mix : {Mix::neo_hookean, Mix::stable_neo_hookean}) {
    RandomBlock b = random_block(4, 7, 0.05);
    if (mix != Mix::neo_hookean) assign_kinds(mix, &b);
    // Push one node through its element: the volume ratio turns negative.
    const std::int32_t n = b.nodes[8 * 21 + 6];
    for (int i = 0; i < 3; ++i) b.x[3 * n + i] -= 1.5;
    double e_cpu;
    ASSERT_FALSE(elastic_energy(b.block(), b.x.data(), &e_cpu));
    DeviceBlock d(b);
    device::Array<double> x;
    x.upload(b.x);
    device::Reducer reducer;
    double e;
    EXPECT_FALSE(
        device::elastic_evaluate(d.block(b.block().num_elements), x.data(), 1.0, &e, nullptr, nullptr, reducer));
    EXPECT_LT(device::min_volume_ratio(d.block(b.block().num_elements), x.data(), reducer), 0.0);
  }
}

TEST_F(ElementKernelsGpu, InertiaAndBodyForceMatchTheCpu) {
  const RandomBlock b = random_block(7, 11, 0.1);
  const ElementBlock hb = b.block();
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-0.1, 0.1);
  std::vector<double> x_hat(b.x.size());
  for (std::size_t k = 0; k < x_hat.size(); ++k) x_hat[k] = b.x[k] + u(rng);
  DeviceBlock d(b);
  device::Array<double> x, xh, g;
  x.upload(b.x), xh.upload(x_hat);
  device::Reducer reducer;

  // Lumped: masses per dof.
  std::vector<double> node_mass(b.x.size() / 3, 0.0), m(b.x.size());
  lumped_mass(hb, b.rho.data(), node_mass.data());
  for (std::size_t k = 0; k < m.size(); ++k) m[k] = node_mass[k / 3];
  double e_cpu = 0;
  std::vector<double> g_cpu(b.x.size());
  for (std::size_t k = 0; k < m.size(); ++k) {
    const double dk = b.x[k] - x_hat[k];
    e_cpu += 0.5 * m[k] * dk * dk;
    g_cpu[k] = m[k] * dk;
  }
  device::Array<double> dm;
  dm.upload(m);
  EXPECT_LE(std::abs(device::lumped_inertia_energy(dm.data(), xh.data(), x.data(), m.size(), reducer) - e_cpu),
            1e-12 * e_cpu);
  g.resize(m.size());
  g.set_zero();
  device::lumped_inertia_gradient(dm.data(), xh.data(), x.data(), m.size(), g.data());
  EXPECT_LE(max_relative_difference(g_cpu, g.to_host()), 1e-12);

  // Consistent: 64 masses per element.
  std::vector<double> M(64 * static_cast<std::size_t>(hb.num_elements));
  for (int e = 0; e < hb.num_elements; ++e) {
    double X[24];
    for (int a = 0; a < 8; ++a)
      for (int i = 0; i < 3; ++i) X[3 * a + i] = b.reference[3 * b.nodes[8 * e + a] + i];
    hex8_consistent_mass(X, b.rho[e], &M[64 * e]);
  }
  double ec = 0;
  std::fill(g_cpu.begin(), g_cpu.end(), 0.0);
  for (int e = 0; e < hb.num_elements; ++e)
    for (int a = 0; a < 8; ++a)
      for (int bb = 0; bb < 8; ++bb)
        for (int c = 0; c < 3; ++c) {
          const int na = b.nodes[8 * e + a], nb = b.nodes[8 * e + bb];
          const double Mab = M[64 * e + 8 * a + bb];
          ec += 0.5 * Mab * (b.x[3 * na + c] - x_hat[3 * na + c]) * (b.x[3 * nb + c] - x_hat[3 * nb + c]);
          g_cpu[3 * na + c] += Mab * (b.x[3 * nb + c] - x_hat[3 * nb + c]);
        }
  device::Array<double> dM;
  dM.upload(M);
  EXPECT_LE(std::abs(
                device::consistent_inertia_energy(d.block(hb.num_elements), dM.data(), xh.data(), x.data(), reducer) -
                ec),
            1e-12 * ec);
  g.set_zero();
  device::consistent_inertia_gradient(d.block(hb.num_elements), dM.data(), xh.data(), x.data(), g.data());
  EXPECT_LE(max_relative_difference(g_cpu, g.to_host()), 1e-12);

  // Body force: f·x.
  double fx = 0;
  for (std::size_t k = 0; k < m.size(); ++k) fx += m[k] * b.x[k];
  EXPECT_LE(std::abs(device::dot(dm.data(), x.data(), m.size(), reducer) - fx), 1e-12 * std::abs(fx));
}

}  // namespace
}  // namespace dipc
