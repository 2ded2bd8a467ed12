// Backend choice per run (docs/design.md §4.2): -dipc_backend cpu | cuda |
// auto. Each rank takes the GPU of its node-local rank (MPI_Comm_split_type), so `mpirun -n 4`
// on a 4-GPU node puts one rank on each. `auto` stays on the CPU where CUDA is not built, no
// device is present, or a rank holds fewer elements than the measured crossover (below it the
// kernels' launch and transfer latency costs more than the CPU loop saves; docs/performance.md, "GPU").
#pragma once
#include <mpi.h>

#include <string>

#include "forms/form.hpp"

namespace dipc {

// Elements per rank from which `auto` picks the GPU. Measured with bench_step_breakdown on one
// rank of the lent H200 machine (bench/results/crossover_*_h200.csv): seconds per Newton
// iteration CPU / GPU were 0.0179 / 0.0185 at 500 elements and 0.0334 / 0.0315 at 864; from
// there on the GPU's assembly + line search is 5-7x faster and the totals (dominated by the
// same CPU linear solve) favour the GPU or tie within run-to-run noise.
constexpr long kAutoGpuMinElementsPerRank = 1000;

struct BackendChoice {
  MemorySpace space = MemorySpace::host;
  int device = -1;          // CUDA device of this rank, −1 on the CPU
  std::string description;  // for the run header, e.g. "cuda (auto: 125000 elements/rank >= 1000)"
};

// Collective. requested: "cpu", "cuda" or "auto"; elements: this rank's element count.
// Throws std::runtime_error (on every rank alike) for "cuda" without a usable device.
BackendChoice choose_backend(MPI_Comm comm, const std::string& requested, long elements, long auto_min_elements);

// Device memory dipc's own arrays take per element of a rank (element data, COO values, the
// local-array mirrors and scratch), an upper bound used to refuse a run that cannot fit before
// it starts; PETSc's device matrix and hypre's hierarchy come on top when they live there.
std::size_t device_bytes_per_element(bool matrix_on_device);

// Collective. Throws std::runtime_error if any rank's estimate exceeds its device's free memory,
// naming the rank short of the most, its elements, the memory it needs and has, and what to change.
void check_device_memory(MPI_Comm comm, long elements, bool matrix_on_device);

}  // namespace dipc
