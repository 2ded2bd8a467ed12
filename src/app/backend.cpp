#include "app/backend.hpp"

#include <cstdio>
#include <stdexcept>

#include "app/node_place.hpp"
#include "assembly/element_block_part.hpp"
#include "assembly/element_loops.hpp"
#include "device/device_runtime.hpp"

namespace dipc {

BackendChoice choose_backend(MPI_Comm comm, const std::string& requested, long elements, long auto_min_elements) {
  if (requested != "cpu" && requested != "cuda" && requested != "auto")
    throw std::runtime_error("-dipc_backend: unknown backend '" + requested + "' (use cpu, cuda or auto)");
  BackendChoice choice;
  if (requested == "cpu") {
    choice.description = "cpu (requested)";
    return choice;
  }
  const int devices = device::device_count();
  int min_devices = devices;
  MPI_Allreduce(&devices, &min_devices, 1, MPI_INT, MPI_MIN, comm);
  long total = 0;
  int size;
  MPI_Comm_size(comm, &size);
  MPI_Allreduce(&elements, &total, 1, MPI_LONG, MPI_SUM, comm);
  const long per_rank = total / size;
  if (min_devices == 0) {
    if (requested == "cuda")
      throw std::runtime_error(
          device::built_with_cuda()
              ? "-dipc_backend cuda: no CUDA device visible on at least one rank"
              : "-dipc_backend cuda: dipc was built without CUDA (configure with -DDIPC_WITH_CUDA=ON)");
    choice.description = device::built_with_cuda() ? "cpu (auto: no CUDA device)" : "cpu (auto: built without CUDA)";
    return choice;
  }
  char why[160];
  if (requested == "auto" && per_rank < auto_min_elements) {
    std::snprintf(why, sizeof why, "cpu (auto: %ld elements/rank < %ld)", per_rank, auto_min_elements);
    choice.description = why;
    return choice;
  }
  choice.space = MemorySpace::device;
  const NodePlace place = node_place(comm);
  choice.device = place.rank % devices;
  device::select(choice.device);
  if (requested == "auto")
    std::snprintf(why, sizeof why, "cuda (auto: %ld elements/rank >= %ld)", per_rank, auto_min_elements);
  else
    std::snprintf(why, sizeof why, "cuda (requested)");
  choice.description = why;
  // Processes sharing a GPU without CUDA MPS take turns on it, and every kernel launch and
  // synchronisation may wait for the other's time slice. Latency-bound work suffers most:
  // with the CUDA PETSc (BoomerAMG on the device), 5 steps of the default scene spent 13x
  // longer in SNESSolve with 2 ranks on one H100 than with 1 (README "Ranks sharing a GPU").
  int most_ranks = place.ranks;
  MPI_Allreduce(&place.ranks, &most_ranks, 1, MPI_INT, MPI_MAX, comm);
  if (most_ranks > min_devices) {
    std::snprintf(why, sizeof why,
                  "; warning: up to %d ranks share each GPU of a node (one rank per GPU, or CUDA MPS, is faster)",
                  (most_ranks + min_devices - 1) / min_devices);
    choice.description += why;
  }
  return choice;
}

std::size_t device_bytes_per_element(bool matrix_on_device) {
  // A hex mesh has about one node per element (3 dofs). Per element: connectivity, λ, μ and a
  // consistent mass's own 192 values (8 B each, scenes with one); per node: the reference
  // coordinates and 11 mirrored or scratch arrays of 3 doubles (x, gradient, segment x/p/w,
  // inertia x̂ and mass, body force, ...).
  std::size_t bytes = 8 * 4 + 2 * 8 + kMassCooPerElement * 8 + 3 * 8 + 11 * 3 * 8;
  constexpr std::size_t unique_per_element = 3 * 81, blocks_per_element = 27, element_forms = 2;
  if (matrix_on_device) {
    // A device matrix holds each of the ~81 nonzeros of a row once (value + column index), 3
    // rows per node, twice over for the preconditioner setup's copy. The element forms' values
    // are computed and summed chunk by chunk (one chunk's buffer, check_device_memory) into the
    // unique entries through the node-block map (NodeBlockReduction): 4 B per element node pair
    // (64 per element and element form) and, per node block (27 per node), 4 B per element form,
    // 2 B of mask, 4 B of start and the matrix's 4 B column node (DirectMatrix); 8 B per unique
    // entry for the sums, and PETSc's COO maps of the unique entries (8 B each way).
    bytes += 2 * unique_per_element * (8 + 4) + element_forms * 64 * 4 +
             blocks_per_element * (element_forms * 4 + 2 + 4 + 4) + unique_per_element * (8 + 2 * 8);
  } else {
    // The element forms' values (576 elastic, 192 consistent mass) cross to the host matrix.
    bytes += (kElasticCooPerElement + kMassCooPerElement) * 8;
  }
  return bytes;
}

void check_device_memory(MPI_Comm comm, long elements, bool matrix_on_device) {
  const device::MemoryInfo info = device::memory_info();
  const double need = static_cast<double>(elements) * device_bytes_per_element(matrix_on_device) +
                     (matrix_on_device ? static_cast<double>(ElementBlockPart::kDeviceChunkBytes) : 0.0);
  // The rank short of the most memory, named with its share (MPI_MAXLOC over need − free).
  int rank;
  MPI_Comm_rank(comm, &rank);
  struct {
    double shortfall;
    int rank;
  } mine{need - static_cast<double>(info.free_bytes), rank}, worst;
  MPI_Allreduce(&mine, &worst, 1, MPI_DOUBLE_INT, MPI_MAXLOC, comm);
  if (worst.shortfall <= 0) return;
  double facts[3] = {static_cast<double>(elements), need, static_cast<double>(info.free_bytes)};
  MPI_Bcast(facts, 3, MPI_DOUBLE, worst.rank, comm);
  char msg[400];
  std::snprintf(msg, sizeof msg,
                "the scene does not fit on the GPU: rank %d has %.0f elements and needs about %.2f GiB of device "
                "memory (%zu bytes per element) but its device has %.2f GiB free; run on more GPUs (mpirun -n), or "
                "with -dipc_backend cpu",
                worst.rank, facts[0], facts[1] / 1073741824.0, device_bytes_per_element(matrix_on_device),
                facts[2] / 1073741824.0);
  throw std::runtime_error(msg);
}

}  // namespace dipc
