// exchange_ghost_surface (ghost_surface_exchange.hpp).
#include "contact/distributed/ghost_surface_exchange.hpp"

#include <algorithm>
#include <utility>

#include "partition/mpi_exchange.hpp"

namespace dipc {

std::vector<SurfacePrimitiveRecord> exchange_ghost_surface(MPI_Comm comm,
                                                           const std::vector<SurfacePrimitiveRecord>& owned,
                                                           const std::vector<Aabb>& boxes) {
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  Aabb mine = aabb_empty();
  for (const Aabb& b : boxes) aabb_merge(&mine, b);
  std::vector<Aabb> reach(size);
  MPI_Allgather(&mine, 6, MPI_DOUBLE, reach.data(), 6, MPI_DOUBLE, comm);

  std::vector<std::vector<SurfacePrimitiveRecord>> send(size);
  for (int s = 0; s < size; ++s) {
    if (s == rank || aabb_is_empty(reach[s])) continue;
    for (std::size_t i = 0; i < owned.size(); ++i)
      if (aabbs_overlap(boxes[i], reach[s])) send[s].push_back(owned[i]);
  }
  std::vector<SurfacePrimitiveRecord> received = exchange_records(send, comm);
  std::sort(received.begin(), received.end(), [](const SurfacePrimitiveRecord& a, const SurfacePrimitiveRecord& b) {
    return std::make_pair(a.is_face, a.gid) < std::make_pair(b.is_face, b.gid);
  });
  return received;
}

}  // namespace dipc
