// Benchmark of one contact pair's barrier Hessian on the CPU (contact/contact_pair_terms.hpp),
// and of its PSD projection: the 9×9 projection without the translations that
// contact_pair_terms does (contact/geometry/translation_free_psd.hpp) against the full 12×12
// projection with the relative Jacobi criterion that it replaced. Random active point–triangle
// and edge–edge pairs (half each; a point or an edge within d̂ above a triangle or an edge of
// unit size, every distance type); best of -repeat passes; µs per pair on one core.
//
//   bench_contact_hessian [-pairs 10000,100000] [-repeat 3] [-csv out.csv]
#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <random>
#include <vector>

#include "bench_args.hpp"
#include "contact/contact_pair_terms.hpp"

namespace {

using dipc::ContactPairTerms;
using dipc::PairKind;

constexpr double kDhat = 0.05, kKappa = 1e7, kWeight = 1e-5;

struct Pair {
  PairKind kind;
  std::array<double, 12> X;
};

// Active pairs: the lower triangle or edge in the plane z = 0, the point or upper edge at a
// height below d̂, placed anywhere over it (so every closest-feature type occurs).
std::vector<Pair> active_pairs(long n, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-1, 1), height(0.01 * kDhat, 0.95 * kDhat);
  std::vector<Pair> pairs;
  while (static_cast<long>(pairs.size()) < n) {
    Pair p;
    p.kind = pairs.size() % 2 ? PairKind::vertex_triangle : PairKind::edge_edge;
    for (double& x : p.X) x = u(rng);
    const double h = height(rng);
    if (p.kind == PairKind::vertex_triangle) {
      p.X[0] = 0.3 * p.X[0], p.X[1] = 0.3 * p.X[1], p.X[2] = h;  // the point, over the triangle's middle
      p.X[5] = p.X[8] = p.X[11] = 0;
    } else {
      p.X[2] = p.X[5] = h;  // edge a above edge b
      p.X[8] = p.X[11] = 0;
    }
    bool active = false;
    ContactPairTerms t;
    if (dipc::contact_pair_terms(p.kind, p.X.data(), nullptr, nullptr, kDhat * kDhat, kKappa, kWeight, 0, false, false,
                                 false, &active, &t) &&
        active)
      pairs.push_back(p);
  }
  return pairs;
}

// Seconds of the best of `repeat` passes of f over the pairs; `sink` keeps the work.
template <class F>
double best_seconds(const std::vector<Pair>& pairs, int repeat, F f, double* sink) {
  double best = 1e300;
  for (int r = 0; r < repeat; ++r) {
    const auto start = std::chrono::steady_clock::now();
    for (const Pair& p : pairs) *sink += f(p);
    best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  return best;
}

double hessian(const Pair& p, bool project, bool full_projection) {
  bool active;
  ContactPairTerms t;
  dipc::contact_pair_terms(p.kind, p.X.data(), nullptr, nullptr, kDhat * kDhat, kKappa, kWeight, 0, true, true, project,
                           &active, &t);
  if (full_projection) dipc::project_psd<12>(t.H, 12);
  return t.H[13];
}

}  // namespace

int main(int argc, char** argv) {
  dipc::bench::SweepArgs args;
  args.sizes = {10000, 100000};
  args.repeat = 3;
  if (!dipc::bench::parse_sweep_args(argc, argv, "-pairs", &args)) {
    std::fprintf(stderr, "usage: bench_contact_hessian [-pairs N1,N2,...] [-repeat R] [-csv PATH]\n");
    return 2;
  }
  std::mt19937_64 rng(29);
  std::ofstream csv;
  if (!args.csv_path.empty()) {
    csv.open(args.csv_path);
    csv << "pairs,unprojected_us,full_12x12_projection_us,translation_free_projection_us,speedup\n";
  }
  std::printf("%10s %14s %14s %16s %8s\n", "pairs", "unprojected", "+12x12 proj.", "+9x9 (current)", "speedup");
  double sink = 0;
  for (const long n : args.sizes) {
    const auto pairs = active_pairs(n, rng);
    const double per = 1e6 / static_cast<double>(n);
    const double bare = per * best_seconds(pairs, args.repeat, [](const Pair& p) { return hessian(p, false, false); }, &sink);
    const double full = per * best_seconds(pairs, args.repeat, [](const Pair& p) { return hessian(p, false, true); }, &sink);
    const double free = per * best_seconds(pairs, args.repeat, [](const Pair& p) { return hessian(p, true, false); }, &sink);
    std::printf("%10ld %12.3f us %12.3f us %14.3f us %7.2fx\n", n, bare, full, free, full / free);
    if (csv) csv << n << ',' << bare << ',' << full << ',' << free << ',' << full / free << '\n';
  }
  std::fprintf(stderr, "(checksum %g)\n", sink);
  return 0;
}
