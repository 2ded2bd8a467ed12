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

ExchangePlan plan_exchange(const std::vector<std::size_t>& counts, MPI_Comm comm) {
  int size = 0;
  MPI_Comm_size(comm, &size);
  std::string error;
  if (static_cast<int>(counts.size()) != size) error = "exchange_records: one send list per rank is needed";
  ExchangePlan plan;
  plan.send_counts.assign(size, 0);
  plan.send_displs.assign(size, 0);
  std::size_t total_send = 0;
  for (int r = 0; r < size && error.empty(); ++r) {
    if (counts[r] > static_cast<std::size_t>(INT_MAX) || total_send > static_cast<std::size_t>(INT_MAX))
      error = "exchange_records: more records than MPI's int counts allow; use more ranks";
    plan.send_counts[r] = static_cast<int>(counts[r]);
    plan.send_displs[r] = static_cast<int>(total_send);
    total_send += counts[r];
  }
  agree_on_error(comm, error);
  plan.recv_counts.assign(size, 0);
  MPI_Alltoall(plan.send_counts.data(), 1, MPI_INT, plan.recv_counts.data(), 1, MPI_INT, comm);
  plan.recv_displs.assign(size, 0);
  for (int r = 0; r < size; ++r) {
    if (plan.total_recv > static_cast<std::size_t>(INT_MAX)) error = "exchange_records: too many records received";
    plan.recv_displs[r] = static_cast<int>(plan.total_recv);
    plan.total_recv += static_cast<std::size_t>(plan.recv_counts[r]);
  }
  agree_on_error(comm, error);
  return plan;
}

void exchange_bytes(const std::vector<const char*>& send, const ExchangePlan& plan, std::size_t record_bytes, char* out,
                    bool copy_own, MPI_Comm comm) {
  int rank = 0, size = 0;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  const auto bytes = [record_bytes](int records) { return static_cast<std::size_t>(records) * record_bytes; };
  if (copy_own && plan.send_counts[rank])
    std::memcpy(out + bytes(plan.recv_displs[rank]), send[rank], bytes(plan.send_counts[rank]));
  if (size == 1) return;
  // The other ranks' send lists live in separate vectors: pack them into one buffer for
  // MPI_Alltoallv, which moves nothing to or from this rank itself.
  std::vector<int> send_counts = plan.send_counts, recv_counts = plan.recv_counts;
  send_counts[rank] = recv_counts[rank] = 0;
  std::vector<char> packed(bytes(plan.send_displs[size - 1] + plan.send_counts[size - 1]));
  for (int r = 0; r < size; ++r)
    if (send_counts[r]) std::memcpy(packed.data() + bytes(plan.send_displs[r]), send[r], bytes(send_counts[r]));
  MPI_Datatype record;
  MPI_Type_contiguous(static_cast<int>(record_bytes), MPI_BYTE, &record);
  MPI_Type_commit(&record);
  MPI_Alltoallv(packed.data(), send_counts.data(), plan.send_displs.data(), record, out, recv_counts.data(),
                plan.recv_displs.data(), record, comm);
  MPI_Type_free(&record);
}

void fill_from_rank(const ExchangePlan& plan, std::vector<int>* from_rank) {
  if (!from_rank) return;
  from_rank->clear();
  from_rank->reserve(plan.total_recv);
  for (std::size_t r = 0; r < plan.recv_counts.size(); ++r)
    from_rank->insert(from_rank->end(), plan.recv_counts[r], static_cast<int>(r));
}

bool receives_own_only(const ExchangePlan& plan, MPI_Comm comm) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  return plan.total_recv == static_cast<std::size_t>(plan.recv_counts[rank]);
}

}  // namespace detail
}  // namespace dipc
