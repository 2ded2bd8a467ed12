#include "assembly/remote_entry_sums.hpp"

#include <algorithm>
#include <climits>
#include <stdexcept>
#include <utility>

#include "device/mpi_device_buffers.hpp"

namespace dipc {

RemoteEntrySums::~RemoteEntrySums() {
  if (comm_ != MPI_COMM_NULL) MPI_Comm_free(&comm_);
}

void RemoteEntrySums::setup(MPI_Comm comm, const std::vector<std::vector<std::uint32_t>>& send,
                            const std::vector<int>& received_from, std::vector<std::uint32_t> received_slot,
                            std::size_t num_slots, bool on_device) {
  if (comm_ != MPI_COMM_NULL) MPI_Comm_free(&comm_);
  MPI_Comm_dup(comm, &comm_);
  to_.clear(), from_.clear(), gather_.clear();
  for (std::size_t r = 0; r < send.size(); ++r) {
    if (send[r].empty()) continue;
    to_.push_back({static_cast<int>(r), gather_.size(), send[r].size()});
    gather_.insert(gather_.end(), send[r].begin(), send[r].end());
  }
  for (std::size_t k = 0; k < received_from.size();) {
    std::size_t e = k;
    while (e < received_from.size() && received_from[e] == received_from[k]) ++e;
    from_.push_back({received_from[k], k, e - k});
    k = e;
  }
  // Messages count in MPI's int; every rank learns when one would not fit, so none waits.
  int fits = 1, all_fit = 1;
  for (const auto* list : {&to_, &from_})
    for (const Neighbour& n : *list) fits = fits && n.count <= static_cast<std::size_t>(INT_MAX);
  MPI_Allreduce(&fits, &all_fit, 1, MPI_INT, MPI_MIN, comm_);
  if (!all_fit)
    throw std::length_error("a rank holds more matrix entries of another rank's rows than one MPI message "
                            "carries; run on more ranks");
  received_slot_ = std::move(received_slot);
  num_slots_ = num_slots;
  on_device_ = on_device;
  send_.assign(gather_.size(), 0.0);
  received_.assign(received_slot_.size(), 0.0);
  if (on_device_) {
    d_gather_.upload(gather_);
    d_send_.resize(gather_.size());
    d_received_.resize(received_slot_.size());
    // Each slot's received values in k order (a counting sort by slot), as sum() adds them.
    std::vector<std::uint32_t> offsets(num_slots_ + 1, 0), sources(received_slot_.size());
    for (std::uint32_t slot : received_slot_) ++offsets[slot + 1];
    for (std::size_t s = 0; s < num_slots_; ++s) offsets[s + 1] += offsets[s];
    std::vector<std::uint32_t> next(offsets.begin(), offsets.end() - 1);
    for (std::size_t k = 0; k < received_slot_.size(); ++k)
      sources[next[received_slot_[k]]++] = static_cast<std::uint32_t>(k);
    d_slot_offsets_.upload(offsets);
    d_slot_sources_.upload(sources);
  }
}

void RemoteEntrySums::exchange(const double* send, double* received) {
  std::vector<MPI_Request> requests;
  requests.reserve(to_.size() + from_.size());
  constexpr int kTag = 1;
  for (const Neighbour& n : from_) {
    requests.emplace_back();
    MPI_Irecv(received + n.begin, static_cast<int>(n.count), MPI_DOUBLE, n.rank, kTag, comm_, &requests.back());
  }
  for (const Neighbour& n : to_) {
    requests.emplace_back();
    MPI_Isend(send + n.begin, static_cast<int>(n.count), MPI_DOUBLE, n.rank, kTag, comm_, &requests.back());
  }
  MPI_Waitall(static_cast<int>(requests.size()), requests.data(), MPI_STATUSES_IGNORE);
}

void RemoteEntrySums::sum(const double* values, double* sums) {
  std::fill(sums, sums + num_slots_, 0.0);
  if (on_device_ && !gather_.empty()) {
    device::gather(d_send_.data(), values, d_gather_.data(), gather_.size());
    device::copy_to_host(send_.data(), d_send_.data(), gather_.size() * sizeof(double));
  } else {
    for (std::size_t k = 0; k < gather_.size(); ++k) send_[k] = values[gather_[k]];
  }
  exchange(send_.data(), received_.data());
  // In the senders' rank order: a fixed order of the terms of every slot.
  for (std::size_t k = 0; k < received_slot_.size(); ++k) sums[received_slot_[k]] += received_[k];
}

void RemoteEntrySums::sum_to_device(const double* values, double* d_sums) {
  if (!device::mpi_device_direct()) {
    host_sums_.resize(num_slots_);
    sum(values, host_sums_.data());
    if (num_slots_) device::copy_to_device(d_sums, host_sums_.data(), num_slots_ * sizeof(double));
    return;
  }
  if (!gather_.empty()) device::gather(d_send_.data(), values, d_gather_.data(), gather_.size());
  // MPI reads the send buffer outside the kernels' stream: it must be complete first.
  device::synchronize();
  exchange(d_send_.data(), d_received_.data());
  device::reduce_coo(d_received_.data(), d_slot_offsets_.data(), d_slot_sources_.data(), num_slots_, d_sums);
}

}  // namespace dipc
