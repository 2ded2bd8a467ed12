// RemoteEntrySums on its own: every rank sends values to the others' slots, in a shuffled
// entry order, and one rank sends to rank 0 alone; each owner's sums must be the senders' values
// added in rank order. Integer values, so the expected sums are exact. The device variant
// (values in device memory) runs where a GPU is present and is skipped elsewhere.
#include <gtest/gtest.h>
#include <mpi.h>

#include <cstdint>
#include <vector>

#include "assembly/remote_entry_sums.hpp"
#include "device/device_runtime.hpp"

namespace dipc {
namespace {

constexpr int kSlots = 5;

// Rank p's value for slot s of rank q.
double value_of(int p, int q, int s) { return 1000.0 * p + 10.0 * q + s; }
// The last rank sends to rank 0 only, so that (on three ranks and more) the other owners skip
// a rank, and rank 0 receives from every other rank.
bool sends(int p, int q, int size) { return p != q && !(p == size - 1 && q != 0); }

void check_sums(bool on_device) {
  int rank, size;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  // This rank's entries: kSlots per other rank, stored in reverse, so entry order and slot
  // order differ.
  std::vector<double> values(static_cast<std::size_t>(kSlots) * size, -1.0);
  std::vector<std::vector<std::uint32_t>> send(size);
  for (int q = 0; q < size; ++q) {
    if (!sends(rank, q, size)) continue;
    for (int s = 0; s < kSlots; ++s) {
      const auto entry = static_cast<std::uint32_t>(kSlots * (size - 1 - q) + (kSlots - 1 - s));
      values[entry] = value_of(rank, q, s);
      send[q].push_back(entry);  // the owner lists them by slot
    }
  }
  std::vector<int> from;
  std::vector<std::uint32_t> slot;
  for (int p = 0; p < size; ++p)
    if (sends(p, rank, size))
      for (int s = 0; s < kSlots; ++s) from.push_back(p), slot.push_back(static_cast<std::uint32_t>(s));
  RemoteEntrySums sums;
  sums.setup(MPI_COMM_WORLD, send, from, slot, kSlots, on_device);
  device::Array<double> d_values("test values");
  if (on_device) d_values.upload(values);
  std::vector<double> got(kSlots, -7.0);
  for (int round = 0; round < 2; ++round) {  // a second sum starts from zero again
    sums.sum(on_device ? d_values.data() : values.data(), got.data());
    for (int s = 0; s < kSlots; ++s) {
      double expected = 0.0;
      for (int p = 0; p < size; ++p)
        if (sends(p, rank, size)) expected += value_of(p, rank, s);
      EXPECT_EQ(got[s], expected) << "rank " << rank << " slot " << s << " round " << round;
    }
  }
}

TEST(RemoteEntrySums, OwnersSumTheOtherRanksValues) { check_sums(false); }

TEST(RemoteEntrySums, DeviceValuesGiveTheSameSums) {
  if (device::device_count() == 0) GTEST_SKIP() << "no CUDA device";
  check_sums(true);
}

}  // namespace
}  // namespace dipc
