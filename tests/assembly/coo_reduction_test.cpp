// CooReduction: the unique (row, col) list sorted by row then column, the map back to the raw
// entries with ascending sources, dropped negative indices, and reduce() against a std::map
// reference, with the owned (dense) row range placed inside, around and outside the rows used.
#include <gtest/gtest.h>

#include <map>
#include <random>
#include <utility>
#include <vector>

#include "assembly/coo_reduction.hpp"

namespace dipc {
namespace {

using Key = std::pair<PetscInt, PetscInt>;

// Raw ids of each kept (row, col), in raw order: the expected map.
std::map<Key, std::vector<std::size_t>> reference_map(const std::vector<PetscInt>& rows,
                                                      const std::vector<PetscInt>& cols) {
  std::map<Key, std::vector<std::size_t>> m;
  for (std::size_t k = 0; k < rows.size(); ++k)
    if (rows[k] >= 0 && cols[k] >= 0) m[{rows[k], cols[k]}].push_back(k);
  return m;
}

// The reduction's entries, order, map and sums equal the reference's.
void expect_matches_reference(const std::vector<PetscInt>& rows, const std::vector<PetscInt>& cols,
                              PetscInt dense_begin, PetscInt dense_end) {
  const CooReduction r = CooReduction::build(rows.data(), cols.data(), rows.size(), dense_begin, dense_end);
  const auto ref = reference_map(rows, cols);
  ASSERT_EQ(r.num_raw, rows.size());
  ASSERT_EQ(r.num_unique(), ref.size());
  ASSERT_EQ(r.rows.size(), ref.size());
  ASSERT_EQ(r.cols.size(), ref.size());
  ASSERT_EQ(r.offsets.size(), ref.size() + 1);
  EXPECT_EQ(r.offsets.front(), 0u);
  std::size_t kept = 0;
  for (const auto& entry : ref) kept += entry.second.size();
  EXPECT_EQ(r.offsets.back(), kept);
  EXPECT_EQ(r.sources.size(), kept);

  std::vector<double> raw(rows.size());
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> value(-1, 1);
  for (double& v : raw) v = value(rng);
  std::vector<double> unique(r.num_unique(), -99.0);
  r.reduce(raw.data(), unique.data());

  std::size_t u = 0;
  for (const auto& [key, sources] : ref) {  // std::map iterates by row, then column
    EXPECT_EQ(r.rows[u], key.first) << "entry " << u;
    EXPECT_EQ(r.cols[u], key.second) << "entry " << u;
    const std::vector<std::size_t> got(r.sources.begin() + r.offsets[u], r.sources.begin() + r.offsets[u + 1]);
    EXPECT_EQ(got, sources) << "sources of (" << key.first << ", " << key.second << ")";
    double sum = 0;
    for (std::size_t k : sources) sum += raw[k];
    EXPECT_EQ(unique[u], sum) << "sum of (" << key.first << ", " << key.second << ")";  // same order: same bits
    ++u;
  }
}

TEST(CooReduction, SumsDuplicatesIntoSortedUniqueEntries) {
  // Unsorted, with (2,1) three times and (0,0) twice.
  const std::vector<PetscInt> rows = {2, 0, 1, 2, 0, 2, 1};
  const std::vector<PetscInt> cols = {1, 0, 2, 1, 0, 1, 0};
  const CooReduction r = CooReduction::build(rows.data(), cols.data(), rows.size(), 0, 3);
  EXPECT_EQ(r.rows, (std::vector<PetscInt>{0, 1, 1, 2}));
  EXPECT_EQ(r.cols, (std::vector<PetscInt>{0, 0, 2, 1}));
  EXPECT_EQ(r.offsets, (std::vector<CooReduction::Index>{0, 2, 3, 4, 7}));
  EXPECT_EQ(r.sources, (std::vector<CooReduction::Index>{1, 4, 6, 2, 0, 3, 5}));
  const std::vector<double> raw = {1, 2, 4, 8, 16, 32, 64};
  std::vector<double> unique(4);
  r.reduce(raw.data(), unique.data());
  EXPECT_EQ(unique, (std::vector<double>{2 + 16, 64, 4, 1 + 8 + 32}));
}

TEST(CooReduction, DropsEntriesWithANegativeIndex) {
  const std::vector<PetscInt> rows = {-1, 1, 1, 0, -5, 1};
  const std::vector<PetscInt> cols = {0, -1, 1, 0, -5, 1};
  const CooReduction r = CooReduction::build(rows.data(), cols.data(), rows.size(), 0, 2);
  EXPECT_EQ(r.num_raw, 6u);
  EXPECT_EQ(r.rows, (std::vector<PetscInt>{0, 1}));
  EXPECT_EQ(r.cols, (std::vector<PetscInt>{0, 1}));
  EXPECT_EQ(r.offsets, (std::vector<CooReduction::Index>{0, 1, 3}));
  EXPECT_EQ(r.sources, (std::vector<CooReduction::Index>{3, 2, 5}));
  // Dropped raw values (huge here) never reach a sum.
  const std::vector<double> raw = {1e300, 1e300, 2, 3, 1e300, 5};
  std::vector<double> unique(2);
  r.reduce(raw.data(), unique.data());
  EXPECT_EQ(unique, (std::vector<double>{3, 7}));
}

TEST(CooReduction, EmptyAndAllDroppedInputs) {
  const CooReduction empty = CooReduction::build(nullptr, nullptr, 0, 0, 10);
  EXPECT_EQ(empty.num_unique(), 0u);
  EXPECT_EQ(empty.offsets, (std::vector<CooReduction::Index>{0}));
  empty.reduce(nullptr, nullptr);
  const std::vector<PetscInt> rows = {-1, -2}, cols = {0, 0};
  const CooReduction dropped = CooReduction::build(rows.data(), cols.data(), rows.size(), 0, 10);
  EXPECT_EQ(dropped.num_unique(), 0u);
  EXPECT_TRUE(dropped.sources.empty());
}

TEST(CooReduction, EmptyRowsInsideTheDenseRange) {
  // Rows 100..199 are the dense range but only 3 of them hold entries; 5 and 900 lie outside.
  const std::vector<PetscInt> rows = {150, 900, 100, 5, 150, 199, 900};
  const std::vector<PetscInt> cols = {3, 0, 7, 5, 3, 199, 0};
  expect_matches_reference(rows, cols, 100, 200);
  const CooReduction r = CooReduction::build(rows.data(), cols.data(), rows.size(), 100, 200);
  EXPECT_EQ(r.rows, (std::vector<PetscInt>{5, 100, 150, 199, 900}));
}

TEST(CooReduction, SourcesAscendWithinEachEntryWhateverTheInputOrder) {
  // Every raw entry the same (row, col): one unique entry summing them in raw order.
  const std::size_t n = 1000;
  const std::vector<PetscInt> rows(n, 4), cols(n, 9);
  const CooReduction r = CooReduction::build(rows.data(), cols.data(), n, 0, 8);
  ASSERT_EQ(r.num_unique(), 1u);
  for (std::size_t j = 0; j < n; ++j) EXPECT_EQ(r.sources[j], j);
  // Values whose sum depends on the order: 1, then 1e16 and -1e16 cancelling, ...
  std::vector<double> raw(n, 1e-3);
  raw[0] = 1, raw[1] = 1e16, raw[2] = -1e16;
  double expected = 0;
  for (double v : raw) expected += v;
  double got = 0;
  r.reduce(raw.data(), &got);
  EXPECT_EQ(got, expected);
}

// A random pattern shaped like an element assembly: blocks of dofs, owned range in the middle,
// ghost rows at both ends, shuffled blocks, a few negative indices.
TEST(CooReduction, RandomPatternAgainstAMapReference) {
  std::mt19937_64 rng(2024);
  const PetscInt global = 3000, owned_begin = 1000, owned_end = 2000;
  std::uniform_int_distribution<PetscInt> owned(owned_begin, owned_end - 1), any(0, global - 1);
  std::uniform_int_distribution<int> pick(0, 9), width(1, 24);
  std::vector<PetscInt> rows, cols;
  for (int block = 0; block < 2000; ++block) {
    std::vector<PetscInt> dofs(static_cast<std::size_t>(width(rng)));
    for (PetscInt& d : dofs) d = pick(rng) == 0 ? any(rng) : owned(rng);
    for (PetscInt r : dofs)
      for (PetscInt c : dofs) {
        rows.push_back(pick(rng) == 0 && pick(rng) == 0 ? -1 : r);
        cols.push_back(c);
      }
  }
  SCOPED_TRACE(rows.size());
  expect_matches_reference(rows, cols, owned_begin, owned_end);  // owned range as in the solver
  expect_matches_reference(rows, cols, 0, global);               // every row dense
  expect_matches_reference(rows, cols, 0, 0);                    // every row sparse
  expect_matches_reference(rows, cols, 2900, 5000);              // range overlapping the top
}

TEST(CooReduction, RepeatedBuildsGiveTheSameMap) {
  std::mt19937_64 rng(3);
  std::uniform_int_distribution<PetscInt> index(0, 199);
  std::vector<PetscInt> rows(20000), cols(20000);
  for (std::size_t k = 0; k < rows.size(); ++k) rows[k] = index(rng), cols[k] = index(rng);
  const CooReduction a = CooReduction::build(rows.data(), cols.data(), rows.size(), 50, 150);
  const CooReduction b = CooReduction::build(rows.data(), cols.data(), rows.size(), 50, 150);
  EXPECT_EQ(a.rows, b.rows);
  EXPECT_EQ(a.cols, b.cols);
  EXPECT_EQ(a.offsets, b.offsets);
  EXPECT_EQ(a.sources, b.sources);
}

}  // namespace
}  // namespace dipc
