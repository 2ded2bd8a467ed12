// Benchmark of the CPU element loops (src/assembly/element_loops.hpp) on structured boxes of
// hex8 elements: times the elastic energy, gradient, PSD-projected Hessian into a COO value
// array, the fused energy+gradient+Hessian pass and the COO pattern build, best of several
// repeats, for a list of element counts. Prints a table and optionally writes CSV.
//
//   bench_element_loop [--sizes 10000,100000,1000000] [--repeat 3] [--mem-cap-gib 8]
//                      [--csv out.csv] [--seed 1]
//
// A size is skipped when its largest COO array (576 doubles of values, or 576 int32 rows plus
// 576 int32 cols, per element; they are never allocated together) would exceed the cap.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <iostream>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "assembly/element_loops.hpp"
#include "physics/neo_hookean.hpp"

namespace {

struct Options {
  std::vector<long long> sizes = {10000, 100000, 1000000};
  int repeat = 3;
  double mem_cap_gib = 8.0;
  std::string csv;
  std::uint64_t seed = 1;
};

[[noreturn]] void usage_error(const std::string& message) {
  std::cerr << "bench_element_loop: " << message
            << "\nusage: bench_element_loop [--sizes N1,N2,...] [--repeat R>=1] [--mem-cap-gib G] [--csv PATH]"
               " [--seed S]\n";
  std::exit(2);
}

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) usage_error("option " + arg + " needs a value");
      return argv[++i];
    };
    try {
      if (arg == "--sizes") {
        o.sizes.clear();
        std::stringstream list(value());
        std::string item;
        while (std::getline(list, item, ',')) {
          const long long n = std::stoll(item);
          if (n < 1 || n > 2000000000LL) usage_error("size '" + item + "' is outside [1, 2e9]");
          o.sizes.push_back(n);
        }
        if (o.sizes.empty()) usage_error("--sizes is empty");
      } else if (arg == "--repeat") {
        o.repeat = std::stoi(value());
        if (o.repeat < 1) usage_error("--repeat must be >= 1");
      } else if (arg == "--mem-cap-gib") {
        o.mem_cap_gib = std::stod(value());
      } else if (arg == "--csv") {
        o.csv = value();
      } else if (arg == "--seed") {
        o.seed = std::stoull(value());
      } else if (arg == "--help" || arg == "-h") {
        usage_error("help");
      } else {
        usage_error("unknown option '" + arg + "'");
      }
    } catch (const std::logic_error&) {
      usage_error("bad value for " + arg);
    }
  }
  return o;
}

// nx*ny*nz elements of edge h on a grid, nodes jittered by up to 10% of h (non-planar faces),
// materials varying per element, and a trial state x = small random stretch + jitter so every
// quadrature point sees a different, non-trivial F.
struct BoxMesh {
  int nx, ny, nz;
  std::vector<std::int32_t> nodes;
  std::vector<double> reference, x, lambda, mu;
  std::vector<std::int64_t> local_to_global;
  dipc::ElementBlock view() const {
    dipc::ElementBlock b;
    b.num_elements = static_cast<int>(lambda.size());
    b.nodes = nodes.data();
    b.reference = reference.data();
    b.lambda = lambda.data();
    b.mu = mu.data();
    return b;
  }
};

BoxMesh make_box(long long target_elements, std::uint64_t seed) {
  BoxMesh m;
  m.nx = m.ny = std::max(1, static_cast<int>(std::cbrt(static_cast<double>(target_elements))));
  m.nz = static_cast<int>((target_elements + static_cast<long long>(m.nx) * m.ny - 1) /
                          (static_cast<long long>(m.nx) * m.ny));
  const long long num_nodes = static_cast<long long>(m.nx + 1) * (m.ny + 1) * (m.nz + 1);
  const long long num_elements = static_cast<long long>(m.nx) * m.ny * m.nz;
  if (num_nodes > INT32_MAX || num_elements > INT32_MAX)
    throw std::runtime_error("bench_element_loop: box of " + std::to_string(target_elements) +
                             " elements exceeds 32-bit local ids");
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> jitter(-0.1, 0.1), small(-0.02, 0.02), stretch(0.9, 1.1);
  const double h = 1.0;
  auto node_id = [&](int i, int j, int k) { return i + (m.nx + 1) * (j + static_cast<long long>(m.ny + 1) * k); };
  m.reference.resize(3 * num_nodes);
  m.x.resize(3 * num_nodes);
  m.local_to_global.resize(num_nodes);
  const double s[3] = {stretch(rng), stretch(rng), stretch(rng)};
  for (int k = 0; k <= m.nz; ++k)
    for (int j = 0; j <= m.ny; ++j)
      for (int i = 0; i <= m.nx; ++i) {
        const long long n = node_id(i, j, k);
        const double X[3] = {h * (i + jitter(rng)), h * (j + jitter(rng)), h * (k + jitter(rng))};
        for (int c = 0; c < 3; ++c) {
          m.reference[3 * n + c] = X[c];
          m.x[3 * n + c] = s[c] * X[c] + h * small(rng);
        }
        m.local_to_global[n] = n;
      }
  m.nodes.reserve(8 * num_elements);
  // Hex8 corner order (mesh/hex_mesh.hpp): 0:(0,0,0) 1:(1,0,0) 2:(1,1,0) 3:(0,1,0), then z+1.
  const int di[8] = {0, 1, 1, 0, 0, 1, 1, 0}, dj[8] = {0, 0, 1, 1, 0, 0, 1, 1}, dk[8] = {0, 0, 0, 0, 1, 1, 1, 1};
  for (int k = 0; k < m.nz; ++k)
    for (int j = 0; j < m.ny; ++j)
      for (int i = 0; i < m.nx; ++i) {
        for (int a = 0; a < 8; ++a)
          m.nodes.push_back(static_cast<std::int32_t>(node_id(i + di[a], j + dj[a], k + dk[a])));
        double lambda, mu;
        dipc::lame_parameters(1e6 * (1.0 + 0.5 * ((i + j + k) % 3)), 0.3 + 0.05 * (k % 4), &lambda, &mu);
        m.lambda.push_back(lambda);
        m.mu.push_back(mu);
      }
  return m;
}

double best_time(int repeat, const std::function<void()>& body) {
  double best = 1e300;
  for (int r = 0; r < repeat; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    body();
    const auto t1 = std::chrono::steady_clock::now();
    best = std::min(best, std::chrono::duration<double>(t1 - t0).count());
  }
  return best;
}

struct Row {
  long long elements;
  std::string phase;
  double seconds;
  double coo_bytes;  // COO bytes written by the phase, 0 if none
};

void require(bool ok, const char* phase) {
  if (!ok) throw std::runtime_error(std::string("bench_element_loop: ") + phase + " rejected an inverted element");
}

}  // namespace

int main(int argc, char** argv) {
  const Options opt = parse(argc, argv);
  std::vector<Row> rows;
  std::printf("%12s  %-22s %12s %14s %14s\n", "elements", "phase", "seconds", "elements/s", "COO GB/s");
  try {
    for (long long target : opt.sizes) {
      const double coo_bytes_per_element = dipc::kElasticCooPerElement * sizeof(double);
      const double cap_bytes = opt.mem_cap_gib * 1024.0 * 1024.0 * 1024.0;
      if (coo_bytes_per_element * target > cap_bytes) {
        std::printf("%12lld  skipped: COO arrays need %.2f GiB > cap %.2f GiB (--mem-cap-gib)\n", target,
                    coo_bytes_per_element * target / 1073741824.0, opt.mem_cap_gib);
        continue;
      }
      const BoxMesh mesh = make_box(target, opt.seed);
      const dipc::ElementBlock block = mesh.view();
      const long long n = block.num_elements;
      if (!(dipc::min_volume_ratio(block, mesh.x.data(), nullptr) > 0))
        throw std::runtime_error("bench_element_loop: generated state is inverted");
      const double value_bytes = coo_bytes_per_element * n;
      auto record = [&](const std::string& phase, double seconds, double coo_bytes) {
        rows.push_back({n, phase, seconds, coo_bytes});
        if (coo_bytes > 0)
          std::printf("%12lld  %-22s %12.6f %14.4g %14.3f\n", n, phase.c_str(), seconds, n / seconds,
                      coo_bytes / seconds / 1e9);
        else
          std::printf("%12lld  %-22s %12.6f %14.4g %14s\n", n, phase.c_str(), seconds, n / seconds, "-");
        std::fflush(stdout);
      };
      {
        std::vector<double> g(mesh.x.size(), 0.0);
        // Pre-touched so page faults of the first write are not timed.
        std::vector<double> coo_values(static_cast<std::size_t>(dipc::kElasticCooPerElement) * n, 0.0);
        double energy = 0;
        record("energy",
               best_time(opt.repeat, [&] { require(dipc::elastic_energy(block, mesh.x.data(), &energy), "energy"); }),
               0);
        record("gradient",
               best_time(opt.repeat,
                         [&] {
                           std::fill(g.begin(), g.end(), 0.0);
                           require(dipc::elastic_gradient(block, mesh.x.data(), g.data()), "gradient");
                         }),
               0);
        record("hessian_coo",
               best_time(opt.repeat,
                         [&] { require(dipc::elastic_hessian(block, mesh.x.data(), coo_values.data()), "hessian"); }),
               value_bytes);
        record("fused_e_g_h",
               best_time(opt.repeat,
                         [&] {
                           std::fill(g.begin(), g.end(), 0.0);
                           require(dipc::elastic_energy_gradient_hessian(block, mesh.x.data(), &energy, g.data(),
                                                                         coo_values.data()),
                                   "fused");
                         }),
               value_bytes);
        record("min_volume_ratio",
               best_time(opt.repeat, [&] { dipc::min_volume_ratio(block, mesh.x.data(), nullptr); }), 0);
      }
      {
        std::vector<std::int32_t> coo_rows, coo_cols;
        dipc::elastic_coo_pattern(block, mesh.local_to_global.data(), &coo_rows, &coo_cols);  // allocate + touch
        record("coo_pattern",
               best_time(opt.repeat,
                         [&] { dipc::elastic_coo_pattern(block, mesh.local_to_global.data(), &coo_rows, &coo_cols); }),
               2.0 * sizeof(std::int32_t) * dipc::kElasticCooPerElement * n);
      }
    }
  } catch (const std::exception& e) {
    std::cerr << e.what() << "\n";
    return 1;
  }
  if (!opt.csv.empty()) {
    std::ofstream out(opt.csv);
    if (!out) {
      std::cerr << "bench_element_loop: cannot open --csv file '" << opt.csv << "'\n";
      return 1;
    }
    out << "elements,phase,seconds,elements_per_second,coo_bytes_per_second,repeats\n";
    out.precision(9);
    for (const Row& r : rows) {
      out << r.elements << ',' << r.phase << ',' << r.seconds << ',' << r.elements / r.seconds << ',';
      if (r.coo_bytes > 0) out << r.coo_bytes / r.seconds;
      out << ',' << opt.repeat << '\n';
    }
    if (!out) {
      std::cerr << "bench_element_loop: write to '" << opt.csv << "' failed\n";
      return 1;
    }
  }
  return 0;
}
