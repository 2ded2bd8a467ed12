// Contact broad phase: contact::find_candidates on the CPU (one core, BVH) against the device
// broad phase (contact/broad_phase/cuda/device_broad_phase.hpp) on the boundary of a bent cube
// with swept boxes, for surfaces of about 10K, 100K and 1M triangles. The device time is one
// search from positions already on the device to sorted candidate lists on the host (what
// ContactForm's prepare_segment pays); the surface upload, paid only when the primitives change,
// is timed apart. Both results are compared pair for pair. Prints a table, writes CSV; without a
// GPU the device columns are 0.
//
//   bench_broad_phase [-triangles 10000,100000,1000000] [-repeat 3] [-csv out.csv]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "bench_args.hpp"
#include "contact/broad_phase/cuda/device_broad_phase.hpp"
#include "contact/broad_phase/find_candidates.hpp"
#include "device/device_runtime.hpp"

namespace {

struct Surface {
  std::vector<double> x0, x1;
  std::vector<std::int32_t> edges, faces;
  int num_vertices() const { return static_cast<int>(x0.size() / 3); }
  dipc::contact::SurfaceView view() const {
    dipc::contact::SurfaceView s;
    s.num_vertices = num_vertices();
    s.x0 = x0.data(), s.x1 = x1.data();
    s.num_edges = static_cast<int>(edges.size() / 2), s.edges = edges.data();
    s.num_faces = static_cast<int>(faces.size() / 3), s.faces = faces.data();
    return s;
  }
};

// The boundary of the unit cube cut into n³ cells (12 n² triangles), bent by a smooth
// deformation, and its end positions after a smooth motion plus noise, each of about half a
// cell: boxes overlap their neighbours' as in a Newton step of a contact solve.
Surface bent_cube(int n, unsigned seed) {
  Surface s;
  std::vector<std::int32_t> id(static_cast<std::size_t>(n + 1) * (n + 1) * (n + 1), -1);
  auto lattice = [n](int i, int j, int k) { return i + (n + 1) * (j + static_cast<std::size_t>(n + 1) * k); };
  for (int k = 0; k <= n; ++k)
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) {
        if (i != 0 && i != n && j != 0 && j != n && k != 0 && k != n) continue;
        id[lattice(i, j, k)] = s.num_vertices();
        const double x = double(i) / n, y = double(j) / n, z = double(k) / n;
        s.x0.insert(s.x0.end(),
                    {x + 0.05 * std::sin(3.1 * y + 0.3) * std::cos(1.7 * z),
                     y + 0.04 * std::sin(2.3 * z + 1.1) + 0.02 * x * x, z + 0.03 * std::cos(2.9 * x - 0.4) * y});
      }
  for (int axis = 0; axis < 3; ++axis)
    for (int side : {0, n})
      for (int v = 0; v < n; ++v)
        for (int u = 0; u < n; ++u) {
          std::int32_t q[4];
          const int du[4] = {0, 1, 1, 0}, dv[4] = {0, 0, 1, 1};
          for (int c = 0; c < 4; ++c) {
            int ijk[3];
            ijk[axis] = side, ijk[(axis + 1) % 3] = u + du[c], ijk[(axis + 2) % 3] = v + dv[c];
            q[c] = id[lattice(ijk[0], ijk[1], ijk[2])];
          }
          s.faces.insert(s.faces.end(), {q[0], q[1], q[2], q[0], q[2], q[3]});
        }
  // The unique edges of the triangles, as (smaller id, larger id) in sorted order.
  std::vector<std::int64_t> keys;
  for (std::size_t f = 0; f < s.faces.size(); f += 3)
    for (int j = 0; j < 3; ++j) {
      const std::int64_t a = s.faces[f + j], b = s.faces[f + (j + 1) % 3];
      keys.push_back(std::min(a, b) << 32 | std::max(a, b));
    }
  std::sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  for (std::int64_t k : keys) s.edges.insert(s.edges.end(), {std::int32_t(k >> 32), std::int32_t(k & 0xffffffff)});
  const double h = 1.0 / n;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> noise(-0.25 * h, 0.25 * h);
  s.x1 = s.x0;
  for (std::size_t k = 0; k < s.x1.size(); ++k)
    s.x1[k] += 0.3 * h * std::sin(5.0 * s.x0[k - k % 3] + static_cast<double>(k % 3)) + noise(rng);
  return s;
}

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

int main(int argc, char** argv) {
  dipc::bench::SweepArgs args{{10000, 100000, 1000000}, 3, ""};
  if (!dipc::bench::parse_sweep_args(argc, argv, "-triangles", &args)) {
    std::fprintf(stderr, "usage: bench_broad_phase [-triangles N,...] [-repeat R] [-csv PATH]\n");
    return 2;
  }
  const std::vector<long>& sizes = args.sizes;
  const int repeat = args.repeat;
  const std::string& csv_path = args.csv_path;
  const bool gpu = dipc::device::device_count() > 0;
  if (gpu) std::printf("GPU %s\n", dipc::device::name(0).c_str());
  FILE* csv = csv_path.empty() ? nullptr : std::fopen(csv_path.c_str(), "w");
  if (csv)
    std::fprintf(csv, "triangles,edges,vertices,inflation,vertex_face,edge_edge,cpu_seconds,gpu_seconds,"
                      "gpu_upload_seconds,cpu_over_gpu,identical\n");
  std::printf("%10s %10s %10s | %10s %10s | %10s | %10s %10s | %8s %9s\n", "triangles", "edges", "vertices", "v-f",
              "e-e", "cpu s", "gpu s", "upload s", "cpu/gpu", "identical");
  for (long target : sizes) {
    const int n = std::max(1, static_cast<int>(std::lround(std::sqrt(target / 12.0))));
    const Surface s = bent_cube(n, 7);
    const double inflation = 0.25 / n;  // d̂/2 with d̂ half a cell
    dipc::contact::Candidates cpu;
    double cpu_best = 1e30;
    for (int r = 0; r < repeat; ++r) {
      const auto start = std::chrono::steady_clock::now();
      dipc::contact::find_candidates(s.view(), inflation, &cpu);
      cpu_best = std::min(cpu_best, seconds_since(start));
    }
    double gpu_best = 0, upload = 0;
    bool identical = false;
    if (gpu) {
      dipc::device::BroadPhaseSurface d;
      d.num_vertices = s.num_vertices(), d.edges = s.edges, d.faces = s.faces;
      dipc::device::DeviceBroadPhase search;
      dipc::device::Array<double> x0("bench x0"), x1("bench x1");
      x0.upload(s.x0), x1.upload(s.x1);
      dipc::device::synchronize();
      auto start = std::chrono::steady_clock::now();
      search.upload(d);
      dipc::device::synchronize();
      upload = seconds_since(start);
      dipc::contact::Candidates dev;
      gpu_best = 1e30;
      for (int r = 0; r < repeat + 1; ++r) {  // the first run pays for allocations and launch setup
        start = std::chrono::steady_clock::now();
        search.find_candidates(x0.data(), x1.data(), inflation, &dev);  // ends with the copies to the host
        if (r > 0) gpu_best = std::min(gpu_best, seconds_since(start));
      }
      identical = dev.vertex_face == cpu.vertex_face && dev.edge_edge == cpu.edge_edge;
    }
    const std::size_t faces = s.faces.size() / 3, edges = s.edges.size() / 2;
    std::printf("%10zu %10zu %10d | %10zu %10zu | %10.4f | %10.4f %10.4f | %8.1f %9s\n", faces, edges, s.num_vertices(),
                cpu.vertex_face.size(), cpu.edge_edge.size(), cpu_best, gpu_best, upload,
                gpu ? cpu_best / gpu_best : 0.0, gpu ? (identical ? "yes" : "NO") : "-");
    if (csv)
      std::fprintf(csv, "%zu,%zu,%d,%.6g,%zu,%zu,%.6g,%.6g,%.6g,%.3f,%d\n", faces, edges, s.num_vertices(), inflation,
                   cpu.vertex_face.size(), cpu.edge_edge.size(), cpu_best, gpu_best, upload,
                   gpu ? cpu_best / gpu_best : 0.0, gpu && identical ? 1 : 0);
    std::fflush(stdout);
  }
  if (!gpu) std::printf("(no CUDA device: GPU columns are 0)\n");
  if (csv) std::fclose(csv);
  return 0;
}
