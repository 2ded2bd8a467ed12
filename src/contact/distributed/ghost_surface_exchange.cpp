// exchange_ghost_surface (ghost_surface_exchange.hpp).
#include "contact/distributed/ghost_surface_exchange.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

#include "partition/mpi_exchange.hpp"
#include "threads/host_threads.hpp"

namespace dipc {

namespace {

// About this many cells describe a rank's surface: with one rank's bodies spread over the
// scene, their common box held most of the other ranks' surfaces (the 125,000-hex stack on 2
// ranks sent 75-100 % of each rank's surface, which the other's broad phase then searched).
// 64 to 256 cells (a flat surface takes more) of 48 B each are what every rank gathers from
// every other.
constexpr double kTargetCells = 64;
constexpr int kMaxCellsPerAxis = 64;

// A grid of roughly cubic cells over `box`: how many along each axis, at least one. A thin
// extent (a flat surface) counts as 1/64 of the longest, so that the cells do not become slabs.
std::array<int, 3> grid_over(const Aabb& box) {
  double extent[3], longest = 0;
  for (int k = 0; k < 3; ++k) longest = std::max(longest, box.hi[k] - box.lo[k]);
  if (!(longest > 0)) return {1, 1, 1};
  for (int k = 0; k < 3; ++k) extent[k] = std::max(box.hi[k] - box.lo[k], longest / kMaxCellsPerAxis);
  const double cell = std::cbrt(extent[0] * extent[1] * extent[2] / kTargetCells);
  std::array<int, 3> n;
  for (int k = 0; k < 3; ++k) n[k] = std::clamp(static_cast<int>(std::ceil(extent[k] / cell)), 1, kMaxCellsPerAxis);
  return n;
}

// The cell of a box: the one holding its centre.
int cell_of(const Aabb& b, const Aabb& grid_box, const std::array<int, 3>& n) {
  int index = 0;
  for (int k = 0; k < 3; ++k) {
    const double extent = grid_box.hi[k] - grid_box.lo[k];
    const double t = extent > 0 ? (0.5 * (b.lo[k] + b.hi[k]) - grid_box.lo[k]) / extent * n[k] : 0.0;
    const int c = t >= n[k] ? n[k] - 1 : t > 0 ? static_cast<int>(t) : 0;  // a NaN centre lands in cell 0
    index = index * n[k] + c;
  }
  return index;
}

}  // namespace

std::vector<SurfacePrimitiveRecord> exchange_ghost_surface(MPI_Comm comm,
                                                           const std::vector<SurfacePrimitiveRecord>& owned,
                                                           const std::vector<Aabb>& boxes) {
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  if (size == 1) return {};

  // This rank's reach: the non-empty cells of a grid over its surface box, each cell's box the
  // union of the boxes whose centres lie in it. Every box lies in its cell's box, so a box of
  // another rank that overlaps one of this rank's boxes overlaps a cell's box: no pair is missed.
  Aabb mine = aabb_empty();
  for (const Aabb& b : boxes) aabb_merge(&mine, b);
  const std::array<int, 3> n = grid_over(mine);
  const std::size_t num_grid = static_cast<std::size_t>(n[0]) * n[1] * n[2];
  std::vector<int> cell(boxes.size());
  std::vector<Aabb> grid(num_grid, aabb_empty());
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    cell[i] = cell_of(boxes[i], mine, n);
    aabb_merge(&grid[static_cast<std::size_t>(cell[i])], boxes[i]);
  }
  std::vector<Aabb> reach_mine;
  std::vector<int> compact(num_grid, -1);  // grid cell -> index in reach_mine
  for (std::size_t c = 0; c < num_grid; ++c)
    if (!aabb_is_empty(grid[c])) compact[c] = static_cast<int>(reach_mine.size()), reach_mine.push_back(grid[c]);

  // Everyone's cells.
  int count = static_cast<int>(reach_mine.size());
  std::vector<int> counts(size), displs(size + 1, 0);
  MPI_Allgather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, comm);
  std::vector<int> value_counts(size), value_displs(size);
  for (int s = 0; s < size; ++s) {
    displs[s + 1] = displs[s] + counts[s];
    value_counts[s] = 6 * counts[s];
    value_displs[s] = 6 * displs[s];
  }
  std::vector<Aabb> reach(static_cast<std::size_t>(displs[size]));
  MPI_Allgatherv(reach_mine.data(), 6 * count, MPI_DOUBLE, reach.data(), value_counts.data(), value_displs.data(),
                 MPI_DOUBLE, comm);

  std::vector<std::vector<SurfacePrimitiveRecord>> send(size);
  for (int s = 0; s < size; ++s) {
    if (s == rank || counts[s] == 0) continue;
    // Ranks whose surfaces are far apart (most of them, on many ranks) are skipped whole.
    Aabb theirs = aabb_empty();
    for (int t = displs[s]; t < displs[s + 1]; ++t) aabb_merge(&theirs, reach[static_cast<std::size_t>(t)]);
    if (!aabbs_overlap(theirs, mine)) continue;
    // Per cell of this rank, the cells of rank s that its box overlaps; a box then is tested
    // against those alone.
    std::vector<std::vector<int>> near(reach_mine.size());
    for (std::size_t c = 0; c < reach_mine.size(); ++c)
      for (int t = displs[s]; t < displs[s + 1]; ++t)
        if (aabbs_overlap(reach_mine[c], reach[static_cast<std::size_t>(t)])) near[c].push_back(t);
    send[s] = parallel_collect<SurfacePrimitiveRecord>(
        owned.size(), [&](std::size_t begin, std::size_t end, std::vector<SurfacePrimitiveRecord>& out) {
          for (std::size_t i = begin; i < end; ++i)
            for (int t : near[static_cast<std::size_t>(compact[static_cast<std::size_t>(cell[i])])])
              if (aabbs_overlap(boxes[i], reach[static_cast<std::size_t>(t)])) {
                out.push_back(owned[i]);
                break;
              }
        });
  }
  std::vector<SurfacePrimitiveRecord> received = exchange_records(send, comm);
  std::sort(received.begin(), received.end(), [](const SurfacePrimitiveRecord& a, const SurfacePrimitiveRecord& b) {
    return std::make_pair(a.is_face, a.gid) < std::make_pair(b.is_face, b.gid);
  });
  return received;
}

}  // namespace dipc
