// Checks every hex8 elastic element must pass (the standard, mean-dilatation and stable
// neo-Hookean elements), over one family of test elements: the gradient against central
// differences of the energy, the exact Hessian against central differences of the gradient,
// and the projected (Newton) Hessian symmetric PSD with the exact element's energy and
// gradient. An element is a function with the signature of hex8_neo_hookean(X, x, lambda, mu,
// energy, gradient, hessian) -> bool.
#pragma once
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "math/symmetric_eigen.hpp"
#include "physics/hex8_elasticity.hpp"
#include "physics/neo_hookean.hpp"
#include "physics_test_support.hpp"

namespace dipc::test {

using Nodes = std::array<double, 24>;

struct ElementCase {
  Nodes X, x;
  double lambda, mu;
};

// `count` distorted reference elements of sizes 0.01, 1 and 7 in turn, each deformed from
// strong compression to stretch (J = 0.3 ... 3) plus per-node noise (so F varies across the
// quadrature points), with E = 3 Pa and 1 MPa and the Poisson ratios `nus` in turn.
inline std::vector<ElementCase> element_cases(std::uint64_t seed, int count, const std::vector<double>& nus) {
  std::mt19937_64 rng(seed);
  std::vector<ElementCase> out;
  const double Js[] = {0.3, 0.8, 1.0, 1.5, 3.0};
  for (int k = 0; k < count; ++k) {
    ElementCase c;
    const double size = k % 3 == 0 ? 0.01 : (k % 3 == 1 ? 1.0 : 7.0);
    c.X = distorted_hex(rng, size, 0.12);
    c.x = deformed_hex(rng, c.X, Js[k % 5], 0.2, 0.04 * size);
    lame_parameters(k % 2 ? 1e6 : 3.0, nus[k % nus.size()], &c.lambda, &c.mu);
    EXPECT_GT(hex8::min_jacobian_determinant(c.X.data()), 0.0);
    EXPECT_GT(hex8_min_volume_ratio(c.X.data(), c.x.data()), 0.0);
    out.push_back(c);
  }
  return out;
}

inline double characteristic_length(const Nodes& X) { return std::abs(X[3 * 6] - X[0]); }

template <class Element>
void expect_gradient_is_central_difference(Element element, const std::vector<ElementCase>& cases) {
  for (const ElementCase& c : cases) {
    double e, g[24], g_fd[24];
    ASSERT_TRUE(element(c.X.data(), c.x.data(), c.lambda, c.mu, &e, g, nullptr));
    ASSERT_TRUE(
        central_difference_gradient(element, c.X, c.x, c.lambda, c.mu, 1e-6 * characteristic_length(c.X), g_fd));
    EXPECT_LT(max_abs_difference(g, g_fd, 24), 1e-6 * max_abs(g, 24));
  }
}

template <class Element, class Exact>
void expect_exact_hessian_is_central_difference(Element element, Exact exact, const std::vector<ElementCase>& cases) {
  for (const ElementCase& c : cases) {
    double H[576], H_fd[576];
    ASSERT_TRUE(exact(c.X.data(), c.x.data(), c.lambda, c.mu, nullptr, nullptr, H));
    ASSERT_TRUE(central_difference_hessian(element, c.X, c.x, c.lambda, c.mu, 1e-6 * characteristic_length(c.X), H_fd));
    EXPECT_LT(max_abs_difference(H, H_fd, 576), 1e-6 * max_abs(H, 576));
    EXPECT_EQ(max_asymmetry(H, 24), 0.0);
  }
}

// Also requires that some case has an indefinite exact Hessian, so that the projection is
// exercised.
template <class Element, class Exact>
void expect_projected_hessian_psd(Element element, Exact exact, const std::vector<ElementCase>& cases) {
  int indefinite_cases = 0;
  for (const ElementCase& c : cases) {
    double e, g[24], H[576], e_exact, g_exact[24], H_exact[576];
    ASSERT_TRUE(element(c.X.data(), c.x.data(), c.lambda, c.mu, &e, g, H));
    ASSERT_TRUE(exact(c.X.data(), c.x.data(), c.lambda, c.mu, &e_exact, g_exact, H_exact));
    EXPECT_EQ(e, e_exact);
    EXPECT_EQ(max_abs_difference(g, g_exact, 24), 0.0);
    EXPECT_EQ(max_asymmetry(H, 24), 0.0);
    double w[24], V[576];
    symmetric_eigen<24>(H, 24, w, V);
    EXPECT_GE(w[0], -1e-10 * w[23]);
    symmetric_eigen<24>(H_exact, 24, w, V);
    if (w[0] < -1e-8 * w[23]) ++indefinite_cases;
  }
  EXPECT_GT(indefinite_cases, 0) << "no case exercised the projection";
}

}  // namespace dipc::test
