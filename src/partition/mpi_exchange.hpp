// Small MPI building blocks of the parallel mesh setup (mesh_slice.hpp, distribute_slices.cpp):
// balanced contiguous blocks of ids, the home rank of an id, an all-to-all of trivially
// copyable records, and errors that one rank finds made every rank's error.
#pragma once
#include <mpi.h>

#include <cstdint>
#include <cstring>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace dipc {

// Ids [0, n) cut into `parts` contiguous blocks whose sizes differ by at most one, the first
// n % parts blocks one longer. Block p is [block_begin(n, parts, p), block_begin(n, parts, p + 1)).
inline std::int64_t block_begin(std::int64_t n, int parts, int p) {
  const std::int64_t base = n / parts, extra = n % parts;
  return p * base + (p < extra ? p : extra);
}
// The block holding id (0 <= id < n): the inverse of block_begin.
inline int block_of(std::int64_t id, std::int64_t n, int parts) {
  if (parts == 1) return 0;  // saves a 64-bit division per call: ~10% of the one-rank partition
  const std::int64_t base = n / parts, extra = n % parts;
  const std::int64_t long_end = extra * (base + 1);
  if (id < long_end) return static_cast<int>(id / (base + 1));
  return static_cast<int>(extra + (id - long_end) / base);
}

// Collective: throws PartitionError on every rank when `local_error` is non-empty on any rank,
// with the message of the lowest failing rank.
void agree_on_error(MPI_Comm comm, const std::string& local_error);

// Collective all-to-all of records: send[r] goes to rank r; the result holds what every rank
// sent here, in rank order, and *from_rank (when given) the source rank of each record. T is
// sent as raw bytes, so it must be trivially copyable and the same type on every rank.
template <class T>
std::vector<T> exchange_records(const std::vector<std::vector<T>>& send, MPI_Comm comm,
                                std::vector<int>* from_rank = nullptr);
// The same, consuming `send` (empty on return): when this rank receives only its own records
// (always on one rank), the result is send[rank] itself, moved instead of copied (at 1M hexes
// on one rank the copies touched ~0.5 GB of fresh pages).
template <class T>
std::vector<T> exchange_records(std::vector<std::vector<T>>&& send, MPI_Comm comm,
                                std::vector<int>* from_rank = nullptr);

// Collective: the sum of `value` over the ranks before this one (0 on rank 0), and the total.
std::int64_t exclusive_prefix(std::int64_t value, MPI_Comm comm, std::int64_t* total = nullptr);

// ----- implementation of the template -----
namespace detail {
// Counts and displacements of one exchange, in records (not bytes), so that they stay inside
// MPI's int range longer.
struct ExchangePlan {
  std::vector<int> send_counts, send_displs, recv_counts, recv_displs;
  std::size_t total_recv = 0;
};
// Collective: exchanges the counts (counts[r] records to rank r).
ExchangePlan plan_exchange(const std::vector<std::size_t>& counts, MPI_Comm comm);
// Collective: sends send[r] (plan.send_counts[r] records of `record_bytes`) to rank r and
// receives into `out` (plan.total_recv records). This rank's own records are copied straight
// into `out`, past MPI (with a balanced numbering most records of the setup stay on their
// rank), unless copy_own is false.
void exchange_bytes(const std::vector<const char*>& send, const ExchangePlan& plan, std::size_t record_bytes, char* out,
                    bool copy_own, MPI_Comm comm);
// The source rank of every received record.
void fill_from_rank(const ExchangePlan& plan, std::vector<int>* from_rank);
// Whether every record this rank receives is its own.
bool receives_own_only(const ExchangePlan& plan, MPI_Comm comm);

template <class T>
ExchangePlan plan_records(const std::vector<std::vector<T>>& send, MPI_Comm comm, std::vector<const char*>& data) {
  static_assert(std::is_trivially_copyable<T>::value, "exchange_records sends raw bytes");
  data.resize(send.size());
  std::vector<std::size_t> counts(send.size());
  for (std::size_t r = 0; r < send.size(); ++r) {
    data[r] = reinterpret_cast<const char*>(send[r].data());
    counts[r] = send[r].size();
  }
  return plan_exchange(counts, comm);
}
}  // namespace detail

template <class T>
std::vector<T> exchange_records(const std::vector<std::vector<T>>& send, MPI_Comm comm, std::vector<int>* from_rank) {
  std::vector<const char*> data;
  const detail::ExchangePlan plan = detail::plan_records(send, comm, data);
  std::vector<T> out(plan.total_recv);
  detail::exchange_bytes(data, plan, sizeof(T), reinterpret_cast<char*>(out.data()), true, comm);
  detail::fill_from_rank(plan, from_rank);
  return out;
}

template <class T>
std::vector<T> exchange_records(std::vector<std::vector<T>>&& send, MPI_Comm comm, std::vector<int>* from_rank) {
  std::vector<const char*> data;
  const detail::ExchangePlan plan = detail::plan_records(send, comm, data);
  std::vector<T> out;
  if (detail::receives_own_only(plan, comm)) {
    int rank = 0;
    MPI_Comm_rank(comm, &rank);
    detail::exchange_bytes(data, plan, sizeof(T), nullptr, false, comm);
    out = std::move(send[rank]);
  } else {
    out.resize(plan.total_recv);
    detail::exchange_bytes(data, plan, sizeof(T), reinterpret_cast<char*>(out.data()), true, comm);
  }
  send = std::vector<std::vector<T>>();  // consumed: freed here, as the callers did after copying
  detail::fill_from_rank(plan, from_rank);
  return out;
}

}  // namespace dipc
