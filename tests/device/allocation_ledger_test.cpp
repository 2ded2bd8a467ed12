// AllocationLedger: live allocations summed by name, largest first; released and unknown
// pointers; the per-element summary of the run header; many threads at once.
#include <gtest/gtest.h>

#include <thread>
#include <vector>

#include "device/allocation_ledger.hpp"

namespace dipc::device {
namespace {

TEST(AllocationLedger, SumsLiveAllocationsByNameLargestFirst) {
  AllocationLedger ledger;
  char blocks[4] = {};
  ledger.add(&blocks[0], 100, "sources");
  ledger.add(&blocks[1], 300, "values");
  ledger.add(&blocks[2], 150, "sources");
  ledger.add(&blocks[3], 10, "masks");
  ledger.add(nullptr, 999, "nothing");  // a zero-byte allocation: no pointer, nothing held
  const std::vector<AllocationLedger::Use> uses = ledger.uses();
  ASSERT_EQ(uses.size(), 3u);
  EXPECT_EQ(uses[0].what, "values");
  EXPECT_EQ(uses[0].bytes, 300u);
  EXPECT_EQ(uses[1].what, "sources");
  EXPECT_EQ(uses[1].bytes, 250u);
  EXPECT_EQ(uses[1].allocations, 2u);
  EXPECT_EQ(uses[2].what, "masks");
  EXPECT_EQ(ledger.total_bytes(), 560u);

  ledger.remove(&blocks[1]);
  ledger.remove(&blocks[1]);  // twice: the second is unknown
  int elsewhere = 0;
  ledger.remove(&elsewhere);  // never added
  ledger.remove(nullptr);
  EXPECT_EQ(ledger.total_bytes(), 260u);
  EXPECT_EQ(ledger.uses().front().what, "sources");
}

TEST(AllocationLedger, PerElementSummaryNamesTheLargestAndCountsTheRest) {
  AllocationLedger ledger;
  char blocks[4] = {};
  ledger.add(&blocks[0], 4000, "values");
  ledger.add(&blocks[1], 2000, "sources");
  ledger.add(&blocks[2], 600, "masks");
  ledger.add(&blocks[3], 400, "starts");
  EXPECT_EQ(ledger.per_element(10, 2), "700 B/element: values 400, sources 200, 2 more 100");
  EXPECT_EQ(ledger.per_element(10, 9), "700 B/element: values 400, sources 200, masks 60, starts 40");
  EXPECT_EQ(ledger.per_element(0, 1), "7000 B/element: values 4000, 3 more 3000");  // no elements: per 1
  EXPECT_EQ(AllocationLedger().per_element(5, 3), "0 B/element");
}

TEST(AllocationLedger, ThreadsAddAndRemoveAtOnce) {
  AllocationLedger ledger;
  constexpr int kThreads = 8, kEach = 1000;
  std::vector<char> blocks(kThreads * kEach);
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t)
    threads.emplace_back([&, t] {
      for (int i = 0; i < kEach; ++i) ledger.add(&blocks[t * kEach + i], 8, "x");
      for (int i = 0; i < kEach; i += 2) ledger.remove(&blocks[t * kEach + i]);
    });
  for (auto& th : threads) th.join();
  EXPECT_EQ(ledger.total_bytes(), 8u * kThreads * kEach / 2);
  EXPECT_EQ(ledger.uses().at(0).allocations, static_cast<std::size_t>(kThreads * kEach / 2));
}

}  // namespace
}  // namespace dipc::device
