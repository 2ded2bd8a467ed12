// Assembly throughput: neo-Hookean value + gradient + PSD Hessian into COO values, in elements
// per second, on the GPU (one device, the whole block) and on the CPU with every rank of the
// run evaluating its share at the same time (mpirun -n 16 on the lent machine's 16 cores),
// side by side for each size. The GPU's achieved memory bandwidth is set against the card's
// device-to-device copy bandwidth, measured in the same run. Prints a table, writes CSV.
//
//   mpirun -n R bench_assembly_throughput [-sizes 10000,100000,1000000,4000000] [-repeat 5] [-csv out.csv]
//
// Elements are cubes of a jittered structured block under a random smooth deformation; each
// rank builds its own block of N/R elements for the CPU run, rank 0 one block of N for the GPU.
#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "assembly/cuda/element_kernels.hpp"
#include "assembly/element_loops.hpp"
#include "bench_args.hpp"
#include "device/device_runtime.hpp"

namespace {

struct Block {
  std::vector<std::int32_t> nodes;
  std::vector<double> reference, x, lambda, mu;
  dipc::ElementBlock view() const {
    dipc::ElementBlock b;
    b.num_elements = static_cast<int>(lambda.size());
    b.nodes = nodes.data(), b.reference = reference.data(), b.lambda = lambda.data(), b.mu = mu.data();
    return b;
  }
};

// About n elements as an (m × m × k) block of unit cubes, nodes numbered x fastest.
Block make_block(long n, unsigned seed) {
  const int m = std::max(1, static_cast<int>(std::cbrt(static_cast<double>(n))));
  const int k = std::max(1, static_cast<int>((n + static_cast<long>(m) * m - 1) / (static_cast<long>(m) * m)));
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> jitter(-0.1, 0.1);
  Block b;
  auto id = [m](int i, int j, int l) { return (l * (m + 1) + j) * (m + 1) + i; };
  for (int l = 0; l <= k; ++l)
    for (int j = 0; j <= m; ++j)
      for (int i = 0; i <= m; ++i)
        for (double c : {double(i), double(j), double(l)}) {
          const double X = c + jitter(rng);
          b.reference.push_back(X);
        }
  b.x.resize(b.reference.size());
  // A smooth deformation with bounded gradient (every element stays valid and mildly strained,
  // whatever the block size): x_i = X_i + 0.05 sin(0.37 X_{i+1} + i).
  for (std::size_t p = 0; p < b.x.size(); ++p) {
    const std::size_t node = p / 3, i = p % 3;
    b.x[p] = b.reference[p] + 0.05 * std::sin(0.37 * b.reference[3 * node + (i + 1) % 3] + i);
  }
  long count = 0;
  for (int l = 0; l < k && count < n; ++l)
    for (int j = 0; j < m && count < n; ++j)
      for (int i = 0; i < m && count < n; ++i, ++count) {
        const int c[8] = {id(i, j, l),     id(i + 1, j, l),     id(i + 1, j + 1, l),     id(i, j + 1, l),
                          id(i, j, l + 1), id(i + 1, j, l + 1), id(i + 1, j + 1, l + 1), id(i, j + 1, l + 1)};
        b.nodes.insert(b.nodes.end(), c, c + 8);
        b.lambda.push_back(4e6);
        b.mu.push_back(1e6);
      }
  return b;
}

// Bytes an element's evaluation must move at least: the 576 Hessian values written, its 8
// node ids and λ, μ read, and per node (about one per element) X and x read and the gradient
// read and written.
constexpr double kBytesPerElement = 576 * 8 + 8 * 4 + 2 * 8 + 3 * 8 * 4;

}  // namespace

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  int rank, ranks;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &ranks);
  dipc::bench::SweepArgs args{{10000, 100000, 1000000, 4000000}, 5, ""};
  if (!dipc::bench::parse_sweep_args(argc, argv, "-sizes", &args)) {
    if (rank == 0) std::fprintf(stderr, "usage: bench_assembly_throughput [-sizes N,...] [-repeat R] [-csv PATH]\n");
    MPI_Finalize();
    return 2;
  }
  const std::vector<long>& sizes = args.sizes;
  const int repeat = args.repeat;
  const std::string& csv_path = args.csv_path;
  const bool gpu = rank == 0 && dipc::device::device_count() > 0;
  double copy_bandwidth = 0;  // bytes read + written per second by cudaMemcpy device-to-device
  if (gpu) {
    const std::size_t n = std::size_t(1) << 28;  // 2 GiB of doubles
    dipc::device::Array<double> a, b;
    a.resize(n), b.resize(n);
    a.set_zero();
    double best = 1e30;
    for (int r = 0; r < 5; ++r) {
      dipc::device::synchronize();
      const double t0 = MPI_Wtime();
      dipc::device::copy_on_device(b.data(), a.data(), n * sizeof(double));
      dipc::device::synchronize();
      best = std::min(best, MPI_Wtime() - t0);
    }
    copy_bandwidth = 2.0 * n * sizeof(double) / best;
    std::printf("GPU %s: device-to-device copy %.0f GB/s (read + write)\n", dipc::device::name(0).c_str(),
                copy_bandwidth / 1e9);
  }
  FILE* csv = (rank == 0 && !csv_path.empty()) ? std::fopen(csv_path.c_str(), "w") : nullptr;
  if (csv)
    std::fprintf(csv, "elements,cpu_ranks,cpu_seconds,cpu_elements_per_s,gpu_seconds,gpu_elements_per_s,"
                      "gpu_bandwidth_GBs,copy_bandwidth_GBs,gpu_over_cpu\n");
  if (rank == 0)
    std::printf("%10s | %12s %14s | %12s %14s %10s %8s | %8s\n", "elements", "cpu s", "cpu elem/s", "gpu s",
                "gpu elem/s", "gpu GB/s", "of copy", "gpu/cpu");
  for (long n : sizes) {
    // CPU: every rank its share, all at once; the slowest rank sets the time.
    const long share = n / ranks + (rank < n % ranks ? 1 : 0);
    double cpu_best = 1e30;
    {
      const Block b = make_block(share, 1 + rank);
      std::vector<double> g(b.x.size()), coo(dipc::kElasticCooPerElement * b.lambda.size());
      for (int r = 0; r < repeat; ++r) {
        std::fill(g.begin(), g.end(), 0.0);
        double e;
        MPI_Barrier(MPI_COMM_WORLD);
        const double t0 = MPI_Wtime();
        dipc::elastic_energy_gradient_hessian(b.view(), b.x.data(), &e, g.data(), coo.data());
        double t = MPI_Wtime() - t0, worst;
        MPI_Allreduce(&t, &worst, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
        cpu_best = std::min(cpu_best, worst);
      }
    }
    // GPU: the whole block on rank 0's device.
    double gpu_best = 0;
    if (gpu) {
      const Block b = make_block(n, 7);
      dipc::device::Array<std::int32_t> nodes;
      dipc::device::Array<double> X, x, lambda, mu, g, coo;
      nodes.upload(b.nodes), X.upload(b.reference), x.upload(b.x), lambda.upload(b.lambda), mu.upload(b.mu);
      g.resize(b.x.size());
      coo.resize(dipc::kElasticCooPerElement * b.lambda.size());
      dipc::ElementBlock d;
      d.num_elements = static_cast<int>(b.lambda.size());
      d.nodes = nodes.data(), d.reference = X.data(), d.lambda = lambda.data(), d.mu = mu.data();
      dipc::device::Reducer reducer;
      gpu_best = 1e30;
      for (int r = 0; r < repeat + 1; ++r) {  // the first run pays for the launch setup
        g.set_zero();
        dipc::device::synchronize();
        const double t0 = MPI_Wtime();
        double e;
        dipc::device::elastic_evaluate(d, x.data(), 1.0, &e, g.data(), coo.data(), reducer);  // syncs on the energy
        if (r > 0) gpu_best = std::min(gpu_best, MPI_Wtime() - t0);
      }
    }
    if (rank == 0) {
      const double cpu_rate = n / cpu_best, gpu_rate = gpu ? n / gpu_best : 0;
      const double bw = gpu ? n * kBytesPerElement / gpu_best : 0;
      std::printf("%10ld | %12.5f %14.4g | %12.5f %14.4g %10.0f %7.0f%% | %8.2f\n", n, cpu_best, cpu_rate, gpu_best,
                  gpu_rate, bw / 1e9, copy_bandwidth > 0 ? 100 * bw / copy_bandwidth : 0.0,
                  gpu ? gpu_rate / cpu_rate : 0.0);
      if (csv)
        std::fprintf(csv, "%ld,%d,%.6g,%.6g,%.6g,%.6g,%.1f,%.1f,%.3f\n", n, ranks, cpu_best, cpu_rate, gpu_best,
                     gpu_rate, bw / 1e9, copy_bandwidth / 1e9, gpu ? gpu_rate / cpu_rate : 0.0);
      std::fflush(stdout);
    }
  }
  if (!gpu && rank == 0) std::printf("(no CUDA device: GPU columns are 0)\n");
  if (csv) std::fclose(csv);
  MPI_Finalize();
  return 0;
}
