// The contact Hessian's PSD projection on the 9 dimensions its translations leave
// (contact/geometry/translation_free_psd.hpp) against the full 12×12 projection
// (math/symmetric_eigen.hpp, relative Jacobi criterion), on unprojected barrier Hessians of
// every point–triangle and edge–edge distance type, mollified edge pairs included.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <vector>

#include "contact/contact_pair_terms.hpp"
#include "contact/geometry/translation_free_psd.hpp"
#include "geometry_test_support.hpp"

namespace dipc::contact {
namespace {

using test::Stencil;

// Unprojected barrier Hessians (κ = 1e7, weight 1e-5, d̂ = 0.05 on stencils of unit size) of
// random active pairs of every distance type; edge–edge stencils with a mollifier threshold
// above their cross product too.
std::vector<std::array<double, 144>> barrier_hessians() {
  std::mt19937_64 rng(29);
  const double dhat = 0.05;
  std::vector<std::array<double, 144>> out;
  auto add = [&](PairKind kind, const Stencil& s, double eps_x) {
    const auto X = s.flat();
    bool active = false;
    ContactPairTerms t;
    if (contact_pair_terms(kind, X.data(), nullptr, nullptr, dhat * dhat, 1e7, 1e-5, eps_x, true, true, false, &active,
                           &t) &&
        active) {
      std::array<double, 144> H;
      std::copy(t.H, t.H + 144, H.begin());
      out.push_back(H);
    }
  };
  for (int rep = 0; rep < 40; ++rep) {
    const double gap = dhat * test::uniform(rng, 0.01, 0.95);
    for (int type = 0; type < 7; ++type) add(PairKind::vertex_triangle, test::point_triangle_of_type(rng, type, gap), 0);
    for (const auto& f : test::kEdgeEdgeFeatures) {
      const Stencil s = test::edge_edge_of_features(rng, f[0], f[1], gap);
      add(PairKind::edge_edge, s, 0);
      add(PairKind::edge_edge, s, 1e3);  // every pair mollified
    }
  }
  return out;
}

double max_abs(const std::array<double, 144>& H) {
  double m = 0;
  for (double v : H) m = std::max(m, std::abs(v));
  return m;
}

TEST(TranslationFreePsd, BarrierHessiansHaveTheTranslationsInTheirNullSpace) {
  // The premise: every row sums to zero over the four points' blocks, per axis.
  for (const auto& H : barrier_hessians()) {
    const double scale = max_abs(H);
    for (int i = 0; i < 12; ++i)
      for (int c = 0; c < 3; ++c) {
        const double row_sum = H[12 * i + c] + H[12 * i + 3 + c] + H[12 * i + 6 + c] + H[12 * i + 9 + c];
        ASSERT_LE(std::abs(row_sum), 1e-9 * scale) << "row " << i << " axis " << c;
      }
  }
}

TEST(TranslationFreePsd, EqualsTheFullProjection) {
  const auto hessians = barrier_hessians();
  ASSERT_GT(hessians.size(), 700u);
  double worst = 0;
  int indefinite = 0;
  for (const auto& H : hessians) {
    std::array<double, 144> full = H, reduced = H;
    project_psd<12>(full.data(), 12);
    project_translation_free_psd(reduced.data());
    const double scale = max_abs(H);
    double diff = 0;
    for (int k = 0; k < 144; ++k) diff = std::max(diff, std::abs(full[k] - reduced[k]));
    worst = std::max(worst, diff / scale);
    for (int i = 0; i < 12; ++i)
      for (int j = 0; j < 12; ++j) ASSERT_EQ(reduced[12 * i + j], reduced[12 * j + i]);
    // Positive semi-definite to rounding, and the translations still in the null space.
    double w[12], V[144];
    symmetric_eigen<12>(reduced.data(), 12, w, V);
    ASSERT_GE(w[0], -1e-13 * scale);
    for (int i = 0; i < 12; ++i)
      for (int c = 0; c < 3; ++c)
        ASSERT_LE(std::abs(reduced[12 * i + c] + reduced[12 * i + 3 + c] + reduced[12 * i + 6 + c] +
                           reduced[12 * i + 9 + c]),
                  1e-13 * scale);
    symmetric_eigen<12>(H.data(), 12, w, V);
    indefinite += w[0] < -1e-8 * scale;
  }
  EXPECT_LE(worst, 1e-12);
  // The projection has work to do on a good part of them (b' ∇²d is indefinite).
  EXPECT_GT(indefinite, static_cast<int>(hessians.size() / 10));
}

TEST(TranslationFreePsd, LeavesAPositiveSemiDefiniteHessianAsItIs) {
  for (auto H : barrier_hessians()) {
    project_psd<12>(H.data(), 12);
    const auto before = H;
    project_translation_free_psd(H.data());
    const double scale = max_abs(before);
    for (int k = 0; k < 144; ++k) ASSERT_NEAR(H[k], before[k], 1e-13 * scale);
  }
}

}  // namespace
}  // namespace dipc::contact
