// exchange_records, agree_on_error and exclusive_prefix (see mpi_exchange.hpp).
#include "partition/mpi_exchange.hpp"

#include <climits>

#include "partition/partition_error.hpp"

namespace dipc {

void agree_on_error(MPI_Comm comm, const std::string& local_error) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  const int mine = local_error.empty() ? INT_MAX : rank;
  int first = INT_MAX;
  MPI_Allreduce(&mine, &first, 1, MPI_INT, MPI_MIN, comm);
  if (first == INT_MAX) return;
  std::string message = local_error;
  int length = static_cast<int>(message.size());
  MPI_Bcast(&length, 1, MPI_INT, first, comm);
  message.resize(static_cast<std::size_t>(length));
  MPI_Bcast(message.data(), length, MPI_CHAR, first, comm);
  if (rank == first) throw PartitionError(message);
  throw PartitionError(message + " (reported by rank " + std::to_string(first) + ")");
}

std::int64_t exclusive_prefix(std::int64_t value, MPI_Comm comm, std::int64_t* total) {
  std::int64_t before = 0;
  MPI_Exscan(&value, &before, 1, MPI_INT64_T, MPI_SUM, comm);
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  if (rank == 0) before = 0;  // MPI_Exscan leaves rank 0's result undefined
  if (total) MPI_Allreduce(&value, total, 1, MPI_INT64_T, MPI_SUM, comm);
  return before;
}

namespace detail {

std::vector<char> exchange_bytes(const std::vector<const char*>& send, const std::vector<std::size_t>& counts,
                                 std::size_t record_bytes, MPI_Comm comm, std::vector<int>* recv_counts) {
  int size = 0;
  MPI_Comm_size(comm, &size);
  std::string error;
  if (static_cast<int>(counts.size()) != size) error = "exchange_records: one send list per rank is needed";
  std::vector<int> send_counts(size, 0), send_displs(size, 0);
  std::size_t total_send = 0;
  for (int r = 0; r < size && error.empty(); ++r) {
    if (counts[r] > static_cast<std::size_t>(INT_MAX) || total_send > static_cast<std::size_t>(INT_MAX))
      error = "exchange_records: more records than MPI's int counts allow; use more ranks";
    send_counts[r] = static_cast<int>(counts[r]);
    send_displs[r] = static_cast<int>(total_send);
    total_send += counts[r];
  }
  agree_on_error(comm, error);
  recv_counts->assign(size, 0);
  MPI_Alltoall(send_counts.data(), 1, MPI_INT, recv_counts->data(), 1, MPI_INT, comm);
  std::vector<int> recv_displs(size, 0);
  std::size_t total_recv = 0;
  for (int r = 0; r < size; ++r) {
    if (total_recv > static_cast<std::size_t>(INT_MAX)) error = "exchange_records: too many records received";
    recv_displs[r] = static_cast<int>(total_recv);
    total_recv += static_cast<std::size_t>((*recv_counts)[r]);
  }
  agree_on_error(comm, error);
  // The send lists live in separate vectors: pack them into one buffer for MPI_Alltoallv.
  std::vector<char> packed(total_send * record_bytes);
  for (int r = 0; r < size; ++r)
    if (counts[r]) std::memcpy(packed.data() + send_displs[r] * record_bytes, send[r], counts[r] * record_bytes);
  MPI_Datatype record;
  MPI_Type_contiguous(static_cast<int>(record_bytes), MPI_BYTE, &record);
  MPI_Type_commit(&record);
  std::vector<char> received(total_recv * record_bytes);
  MPI_Alltoallv(packed.data(), send_counts.data(), send_displs.data(), record, received.data(), recv_counts->data(),
                recv_displs.data(), record, comm);
  MPI_Type_free(&record);
  return received;
}

}  // namespace detail
}  // namespace dipc
