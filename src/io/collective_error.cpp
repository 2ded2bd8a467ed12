// Consistent exceptions across ranks (see collective_error.hpp).
#include "io/collective_error.hpp"

#include <stdexcept>
#include <vector>

namespace dipc {

void throw_if_failed_anywhere(MPI_Comm comm, const std::string& local_error) {
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  const int candidate = local_error.empty() ? size : rank;
  int failing_rank = size;
  MPI_Allreduce(&candidate, &failing_rank, 1, MPI_INT, MPI_MIN, comm);
  if (failing_rank == size) return;

  int length = rank == failing_rank ? static_cast<int>(local_error.size()) : 0;
  MPI_Bcast(&length, 1, MPI_INT, failing_rank, comm);
  std::vector<char> message(local_error.begin(), local_error.end());
  message.resize(static_cast<std::size_t>(length));
  MPI_Bcast(message.data(), length, MPI_CHAR, failing_rank, comm);
  std::string text(message.begin(), message.end());
  if (rank != failing_rank && size > 1) text += " (on rank " + std::to_string(failing_rank) + ")";
  throw std::runtime_error(text);
}

}  // namespace dipc
