#include "app/scene_size.hpp"

#include <climits>
#include <cstdio>
#include <fstream>
#include <stdexcept>
#include <string>

#include "app/node_place.hpp"

namespace dipc {

namespace {

// A lower bound on the host memory a run needs per element: 16M hexes on 4 ranks measured 4.9 GB
// per rank, about 1.2 kB per element, so a scene refused at 1 kB per element cannot run.
constexpr double kBytesPerElement = 1000;

// This machine's MemAvailable from /proc/meminfo, in bytes; 0 where it cannot be read, which
// leaves the memory unchecked.
double available_bytes() {
  std::ifstream meminfo("/proc/meminfo");
  std::string key;
  double kib = 0;
  while (meminfo >> key >> kib) {
    if (key == "MemAvailable:") return kib * 1024;
    meminfo.ignore(256, '\n');
  }
  return 0;
}

// MemAvailable summed over the nodes of `comm` (read by one rank per node).
double available_on_all_nodes(MPI_Comm comm) {
  double bytes = node_place(comm).rank == 0 ? available_bytes() : 0;
  MPI_Allreduce(MPI_IN_PLACE, &bytes, 1, MPI_DOUBLE, MPI_SUM, comm);
  return bytes;
}

std::string gigabytes(double bytes) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f GB", bytes / 1e9);
  return text;
}

// "<scene>: geometry[b].box.resolution [nx, ny, nz] (x -dipc_refine r)".
std::string box_key(const Scene& scene, std::size_t b, int refine) {
  const auto& r = scene.bodies[b].box->resolution;
  std::string key = scene.source + ": geometry[" + std::to_string(b) + "].box.resolution [" + std::to_string(r[0]) +
                    ", " + std::to_string(r[1]) + ", " + std::to_string(r[2]) + "]";
  return refine == 1 ? key : key + " x -dipc_refine " + std::to_string(refine);
}

}  // namespace

void check_scene_size(const Scene& scene, int refine, MPI_Comm comm) {
  const double available = available_on_all_nodes(comm);
  double elements = 0;  // exact below 2^53, and far beyond any machine's memory above
  for (std::size_t b = 0; b < scene.bodies.size(); ++b) {
    if (!scene.bodies[b].box) continue;
    double count = 1;
    for (int n : scene.bodies[b].box->resolution) {
      if (static_cast<double>(n) * refine > INT_MAX)
        throw std::runtime_error(box_key(scene, b, refine) + " gives more than " + std::to_string(INT_MAX) +
                                 " elements along an axis");
      count *= static_cast<double>(n) * refine;
    }
    if (count > static_cast<double>(INT64_MAX))
      throw std::runtime_error(box_key(scene, b, refine) + " gives more elements than 64-bit ids can number");
    elements += count;
    const double needed = elements * kBytesPerElement;
    if (available > 0 && needed > available) {
      char count_text[32];
      std::snprintf(count_text, sizeof count_text, "%.0f", count);
      throw std::runtime_error(box_key(scene, b, refine) + " gives " + count_text + " elements, needing about " +
                               gigabytes(needed) + ", more than the " + gigabytes(available) + " available");
    }
  }
}

}  // namespace dipc
