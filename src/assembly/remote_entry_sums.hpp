// RemoteEntrySums: the values of matrix entries that a rank holds for rows another rank owns,
// sent to that owner at every assembly and summed there into slots (one per distinct entry).
//
// The pattern is fixed at setup: each rank knows, per owner, which of its entries go there and
// in which order, and each owner the slot of every value it receives. An assembly then is a
// gather, one message per neighbouring rank and a serial sum. DirectMatrix used a PetscSF for
// this; creating it sorted its millions of leaves by rank (PetscSFSetUpRanks) and took
// 0.25-0.33 s of a rank's setup at 4M hexes on 4 ranks (docs/performance.md, "Setup"), while
// the exchange pattern was already known here.
//
// The sums are deterministic: each slot sums its values from 0 in the order of the sending
// ranks (a slot receives at most one value per rank).
#pragma once
#include <mpi.h>

#include <cstddef>
#include <cstdint>
#include <vector>

#include "device/device_runtime.hpp"

namespace dipc {

class RemoteEntrySums {
 public:
  RemoteEntrySums() = default;
  RemoteEntrySums(const RemoteEntrySums&) = delete;
  RemoteEntrySums& operator=(const RemoteEntrySums&) = delete;
  ~RemoteEntrySums();

  // Collective. send[r]: the entries (indices into sum()'s values) whose values go to rank r,
  // in the order rank r lists them; received_from[k] (ascending) and received_slot[k]: the rank
  // that sends this rank's k-th value and the slot it adds to, k in the senders' rank order
  // and each sender's order. The values of sum() live in device memory where on_device.
  // Throws std::length_error where a message would exceed MPI's int counts.
  void setup(MPI_Comm comm, const std::vector<std::vector<std::uint32_t>>& send, const std::vector<int>& received_from,
             std::vector<std::uint32_t> received_slot, std::size_t num_slots, bool on_device);
  // Collective over the ranks this one exchanges with: sums[s] for the num_slots of setup(), host
  // memory, from the values the other ranks hold. values: this rank's entries (host or device
  // memory, as setup() said).
  void sum(const double* values, double* sums);
  // As sum(), into device memory (d_sums, num_slots of them; setup's on_device). Where MPI takes
  // device pointers (device::mpi_device_direct()) the values are sent and received as device
  // buffers and summed there in the same order, bit for bit as sum(); otherwise through sum()
  // and one copy to the device.
  void sum_to_device(const double* values, double* d_sums);

 private:
  // Posts this rank's receives into `received` and sends from `send` (host or device memory),
  // and waits for all of them.
  void exchange(const double* send, double* received);

  struct Neighbour {
    int rank;
    std::size_t begin, count;  // in the send or the receive buffer
  };
  MPI_Comm comm_ = MPI_COMM_NULL;  // a duplicate: the messages cannot meet other traffic
  std::vector<Neighbour> to_, from_;
  std::vector<std::uint32_t> gather_;         // entries sent, packed by destination rank
  std::vector<std::uint32_t> received_slot_;  // slot of each received value
  std::size_t num_slots_ = 0;
  bool on_device_ = false;
  std::vector<double> send_, received_;
  device::Array<std::uint32_t> d_gather_{"remote entry indices"};
  device::Array<double> d_send_{"remote entry values"};
  // The device-direct path: received values, and per slot the received ones that add to it
  // (offsets into sources, each slot's in the senders' order).
  device::Array<double> d_received_{"received remote entry values"};
  device::Array<std::uint32_t> d_slot_offsets_{"remote slot offsets"}, d_slot_sources_{"remote slot sources"};
  std::vector<double> host_sums_;
};

}  // namespace dipc
