// partition_slice and partition_quality (see slice_partition.hpp).
#include "partition/slice_partition.hpp"

#include <petscmat.h>

#include <algorithm>
#include <climits>
#include <utility>

#include "partition/metis_partition.hpp"
#include "partition/mpi_exchange.hpp"
#include "partition/partition_error.hpp"
#include "partition/rcb_partition.hpp"

// PT-Scotch draws from a pseudo-random generator whose state persists between calls; it is
// reset before each partitioning so that a partitioning does not depend on the ones before it in
// the process (Scotch 7 user's guide, SCOTCH_randomReset); parts can still vary between runs
// (slice_partition.hpp). Declared here to avoid Scotch's header, whose
// SCOTCH_Num width differs between Debian's scotch-int32/-int64 variants; this function has
// no such argument. Without the library at link time the reset is skipped.
#if defined(DIPC_HAVE_SCOTCH_RANDOM_RESET)
extern "C" void SCOTCH_randomReset(void);
#endif

namespace dipc {
namespace {

std::vector<int> metis_on_rank0(const MeshSlice& slice, int size) {
  std::vector<std::vector<Hex>> to_root(size);
  to_root[0] = slice.hexes;
  const std::vector<Hex> all = exchange_records(to_root, slice.comm);  // rank 0: every element, in input order
  std::vector<std::vector<std::int32_t>> parts(size);
  std::string error;
  int rank = 0;
  MPI_Comm_rank(slice.comm, &rank);
  if (rank == 0) {
    try {
      const std::vector<int> part = partition_elements(all, static_cast<std::size_t>(slice.num_global_nodes), size);
      for (int r = 0; r < size; ++r) {
        const std::int64_t b = block_begin(slice.num_global_elements, size, r);
        const std::int64_t e = block_begin(slice.num_global_elements, size, r + 1);
        parts[r].assign(part.begin() + b, part.begin() + e);
      }
    } catch (const std::exception& e) {
      error = e.what();
    }
  }
  agree_on_error(slice.comm, error);
  const std::vector<std::int32_t> mine = exchange_records(parts, slice.comm);
  return std::vector<int>(mine.begin(), mine.end());
}

#define DIPC_PETSC_THROW(call)                                                                         \
  do {                                                                                                 \
    const PetscErrorCode ierr_ = (call);                                                               \
    if (ierr_)                                                                                         \
      throw PartitionError(std::string("PT-Scotch partitioning: ") + #call + " failed (PETSc error " + \
                           std::to_string(ierr_) + ")");                                               \
  } while (0)

std::vector<int> ptscotch(const MeshSlice& slice, const FaceMatching& graph, int size) {
  if (!ptscotch_available())
    throw PartitionError(
        "this PETSc was built without PT-Scotch (no PETSC_HAVE_PTSCOTCH): use -dipc_partitioner metis");
  const std::size_t n = slice.hexes.size();
  if (slice.num_global_elements > PETSC_MAX_INT || graph.offsets.back() > PETSC_MAX_INT)
    throw PartitionError("PT-Scotch partitioning: the dual graph exceeds PETSc's " +
                         std::to_string(8 * sizeof(PetscInt)) + "-bit indices");
  // MatCreateMPIAdj takes ownership of ia and ja, which must come from PetscMalloc.
  PetscInt *ia = nullptr, *ja = nullptr;
  DIPC_PETSC_THROW(PetscMalloc1(n + 1, &ia));
  DIPC_PETSC_THROW(PetscMalloc1(std::max<std::size_t>(graph.neighbours.size(), 1), &ja));
  for (std::size_t i = 0; i <= n; ++i) ia[i] = static_cast<PetscInt>(graph.offsets[i]);
  for (std::size_t k = 0; k < graph.neighbours.size(); ++k) ja[k] = static_cast<PetscInt>(graph.neighbours[k]);
#if defined(DIPC_HAVE_SCOTCH_RANDOM_RESET)
  SCOTCH_randomReset();
#endif
  Mat adjacency;
  DIPC_PETSC_THROW(MatCreateMPIAdj(slice.comm, static_cast<PetscInt>(n),
                                   static_cast<PetscInt>(slice.num_global_elements), ia, ja, nullptr, &adjacency));
  MatPartitioning partitioning;
  DIPC_PETSC_THROW(MatPartitioningCreate(slice.comm, &partitioning));
  DIPC_PETSC_THROW(MatPartitioningSetAdjacency(partitioning, adjacency));
  DIPC_PETSC_THROW(MatPartitioningSetNParts(partitioning, size));
  DIPC_PETSC_THROW(MatPartitioningSetType(partitioning, MATPARTITIONINGPTSCOTCH));
  IS is;
  DIPC_PETSC_THROW(MatPartitioningApply(partitioning, &is));
  const PetscInt* values;
  DIPC_PETSC_THROW(ISGetIndices(is, &values));
  std::vector<int> part(values, values + n);
  DIPC_PETSC_THROW(ISRestoreIndices(is, &values));
  DIPC_PETSC_THROW(ISDestroy(&is));
  DIPC_PETSC_THROW(MatPartitioningDestroy(&partitioning));
  DIPC_PETSC_THROW(MatDestroy(&adjacency));
  return part;
}

// The part of every entry of graph.neighbours, in that order. Parts of this slice's elements are
// read here (every neighbour on one rank, most of them with a balanced numbering); the others
// are asked from their home ranks, whose replies come back in the order asked. Linear: the
// sort of (element, part) replies and a binary search per neighbour took 1.0 s for the 6M
// neighbours of a 1M-hex cube on one rank.
std::vector<int> neighbour_parts(const MeshSlice& slice, const FaceMatching& graph, const std::vector<int>& part) {
  int size = 1;
  MPI_Comm_size(slice.comm, &size);
  const std::int64_t ne = slice.num_global_elements, begin = slice.element_begin;
  const std::int64_t end = begin + static_cast<std::int64_t>(slice.hexes.size());
  auto is_local = [begin, end](std::int64_t id) { return id >= begin && id < end; };
  std::vector<std::vector<std::int64_t>> asks(size);
  for (std::int64_t id : graph.neighbours)
    if (!is_local(id)) asks[block_of(id, ne, size)].push_back(id);
  std::vector<int> asker;
  const std::vector<std::int64_t> asked = exchange_records(asks, slice.comm, &asker);
  std::vector<std::vector<std::int32_t>> replies(size);
  for (std::size_t k = 0; k < asked.size(); ++k) replies[asker[k]].push_back(part[asked[k] - begin]);
  const std::vector<std::int32_t> answered = exchange_records(std::move(replies), slice.comm);
  // The replies of home r start after those of the lower homes.
  std::vector<std::size_t> next(size, 0);
  for (int r = 1; r < size; ++r) next[r] = next[r - 1] + asks[r - 1].size();
  std::vector<int> parts(graph.neighbours.size());
  for (std::size_t k = 0; k < parts.size(); ++k) {
    const std::int64_t id = graph.neighbours[k];
    parts[k] = is_local(id) ? part[id - begin] : answered[next[block_of(id, ne, size)]++];
  }
  return parts;
}

}  // namespace

bool ptscotch_available() {
#if defined(PETSC_HAVE_PTSCOTCH)
  return true;
#else
  return false;
#endif
}

Partitioner parse_partitioner(const std::string& name) {
  if (name == "metis") return Partitioner::metis;
  if (name == "ptscotch") return Partitioner::ptscotch;
  if (name == "rcb") return Partitioner::rcb;
  throw PartitionError("unknown partitioner \"" + name + "\" (use metis, ptscotch or rcb)");
}

const char* partitioner_name(Partitioner p) {
  switch (p) {
    case Partitioner::metis: return "metis";
    case Partitioner::ptscotch: return "ptscotch";
    case Partitioner::rcb: return "rcb";
  }
  return "?";
}

std::vector<int> partition_slice(const MeshSlice& slice, const FaceMatching& graph, Partitioner partitioner) {
  int size = 1;
  MPI_Comm_size(slice.comm, &size);
  std::string error;
  if (slice.num_global_elements < size)
    error = "cannot split " + std::to_string(slice.num_global_elements) + " elements into " + std::to_string(size) +
            " parts (more ranks than elements)";
  agree_on_error(slice.comm, error);
  if (size == 1) return std::vector<int>(slice.hexes.size(), 0);
  std::vector<int> part;
  try {
    switch (partitioner) {
      case Partitioner::metis: part = metis_on_rank0(slice, size); break;
      case Partitioner::ptscotch: part = ptscotch(slice, graph, size); break;
      case Partitioner::rcb: part = rcb_partition(slice, size); break;
    }
  } catch (const PartitionError& e) {
    error = e.what();
  }
  agree_on_error(slice.comm, error);
  for (std::size_t e = 0; e < part.size() && error.empty(); ++e)
    if (part[e] < 0 || part[e] >= size)
      error = std::string(partitioner_name(partitioner)) + " gave element " +
              std::to_string(slice.element_begin + static_cast<std::int64_t>(e)) + " part " + std::to_string(part[e]);
  agree_on_error(slice.comm, error);
  return part;
}

PartitionQuality partition_quality(const MeshSlice& slice, const FaceMatching& graph, const std::vector<int>& part) {
  int size = 1;
  MPI_Comm_size(slice.comm, &size);
  const std::int64_t ne = slice.num_global_elements;
  const std::vector<int> other_part = neighbour_parts(slice, graph, part);
  std::int64_t cut_sides = 0;
  for (std::size_t e = 0; e < slice.hexes.size(); ++e)
    for (std::int64_t k = graph.offsets[e]; k < graph.offsets[e + 1]; ++k) cut_sides += other_part[k] != part[e];
  std::vector<std::int64_t> counts(size, 0);
  for (int p : part) ++counts[p];
  MPI_Allreduce(MPI_IN_PLACE, counts.data(), size, MPI_INT64_T, MPI_SUM, slice.comm);
  std::int64_t sums[2] = {cut_sides, static_cast<std::int64_t>(graph.neighbours.size())};
  MPI_Allreduce(MPI_IN_PLACE, sums, 2, MPI_INT64_T, MPI_SUM, slice.comm);
  PartitionQuality q;
  q.edge_cut = sums[0] / 2;  // each cut face is seen from both of its elements
  q.dual_edges = sums[1] / 2;
  q.largest_part = *std::max_element(counts.begin(), counts.end());
  q.smallest_part = *std::min_element(counts.begin(), counts.end());
  q.imbalance = static_cast<double>(q.largest_part) * size / static_cast<double>(ne);
  return q;
}

}  // namespace dipc
