// NodeBlockReduction against CooReduction on the same patterns expanded to scalar COO entries
// (elastic_coo_pattern, consistent_mass_coo_pattern): the same entries, find() locating each,
// and reduce() giving the same bits (the same sums in the same order: forms in order, then
// elements ascending), with the owned (dense) node range inside, around and outside the nodes
// used, and an element mass whose blocks hold only their diagonal; the host's chunked sums
// against reduce(); ReservedBlocks over such blocks.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <random>
#include <stdexcept>
#include <utility>
#include <vector>

#include "assembly/coo_reduction.hpp"
#include "assembly/element_loops.hpp"
#include "assembly/node_block_reduction.hpp"
#include "assembly/reserved_blocks.hpp"

namespace dipc {
namespace {

// Elements of 8 distinct local nodes drawn from [first, first + span).
std::vector<std::int32_t> random_elements(std::mt19937_64& rng, int count, int first, int span) {
  std::vector<std::int32_t> nodes;
  std::vector<std::int32_t> pool(static_cast<std::size_t>(span));
  std::iota(pool.begin(), pool.end(), first);
  for (int e = 0; e < count; ++e) {
    std::shuffle(pool.begin(), pool.end(), rng);
    nodes.insert(nodes.end(), pool.begin(), pool.begin() + 8);
  }
  return nodes;
}

template <class T>
std::vector<PetscInt> to_petsc(const std::vector<T>& v) {
  return std::vector<PetscInt>(v.begin(), v.end());
}

struct Case {
  std::vector<std::int64_t> local_to_global;
  std::vector<std::int32_t> elastic_nodes, mass_nodes;
};

Case random_case(unsigned seed) {
  std::mt19937_64 rng(seed);
  Case c;
  const int num_local = 300;
  // Global ids: a shuffled range with gaps, so that local order is not global order.
  c.local_to_global.resize(num_local);
  for (int n = 0; n < num_local; ++n) c.local_to_global[n] = 1000 + 2 * n;
  std::shuffle(c.local_to_global.begin(), c.local_to_global.end(), rng);
  c.elastic_nodes = random_elements(rng, 400, 0, 250);
  c.mass_nodes = random_elements(rng, 150, 200, 100);  // nodes 250..299 in no elastic element
  return c;
}

void expect_matches_expanded(const Case& c, std::int64_t owned_begin, std::int64_t owned_end) {
  ElementBlock elastic, mass;
  elastic.num_elements = static_cast<int>(c.elastic_nodes.size() / 8);
  elastic.nodes = c.elastic_nodes.data();
  mass.num_elements = static_cast<int>(c.mass_nodes.size() / 8);
  mass.nodes = c.mass_nodes.data();
  const std::size_t elastic_raw = kElasticCooPerElement * static_cast<std::size_t>(elastic.num_elements);

  // Reference: the expanded patterns, elastic then mass, reduced entry by entry.
  std::vector<std::int32_t> r32, c32, mr32, mc32;
  elastic_coo_pattern(elastic, c.local_to_global.data(), &r32, &c32);
  consistent_mass_coo_pattern(mass, c.local_to_global.data(), &mr32, &mc32);
  std::vector<PetscInt> rows = to_petsc(r32), cols = to_petsc(c32);
  rows.insert(rows.end(), mr32.begin(), mr32.end());
  cols.insert(cols.end(), mc32.begin(), mc32.end());
  const CooReduction ref = CooReduction::build(rows.data(), cols.data(), rows.size(),
                                               static_cast<PetscInt>(3 * owned_begin),
                                               static_cast<PetscInt>(3 * owned_end));

  const NodeBlockReduction blocks = NodeBlockReduction::build(
      {{{elastic.num_elements, c.elastic_nodes.data(), c.local_to_global.data(), ElementLayout::elastic}, 0},
       {{mass.num_elements, c.mass_nodes.data(), c.local_to_global.data(), ElementLayout::consistent_mass},
        elastic_raw}},
      owned_begin, owned_end);
  ASSERT_EQ(blocks.num_entries(), ref.num_unique());
  ASSERT_EQ(blocks.forms.size(), 2u);
  EXPECT_EQ(blocks.forms[0].sources.size(), 64 * static_cast<std::size_t>(elastic.num_elements));
  EXPECT_EQ(blocks.forms[1].sources.size(), 64 * static_cast<std::size_t>(mass.num_elements));
  std::size_t diagonal_only = 0;
  for (std::uint16_t m : blocks.block_mask) diagonal_only += m == 0x111 ? 1 : 0;
  EXPECT_GT(diagonal_only, 0u) << "no block of the mass alone: the case does not test partial blocks";

  std::vector<PetscInt> brows, bcols;
  blocks.entries(&brows, &bcols);
  ASSERT_EQ(brows.size(), ref.num_unique());
  std::map<std::pair<PetscInt, PetscInt>, std::size_t> ref_index;
  for (std::size_t u = 0; u < ref.num_unique(); ++u) ref_index[{ref.rows[u], ref.cols[u]}] = u;

  // Values over many magnitudes, so that another summation order would change the bits.
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> mantissa(-1, 1), exponent(-12, 12);
  std::vector<double> raw(rows.size());
  for (double& v : raw) v = mantissa(rng) * std::pow(10.0, exponent(rng));
  std::vector<double> want(ref.num_unique()), got(blocks.num_entries(), -99.0);
  ref.reduce(raw.data(), want.data());
  blocks.reduce(raw.data(), got.data());
  for (std::size_t k = 0; k < brows.size(); ++k) {
    const auto it = ref_index.find({brows[k], bcols[k]});
    ASSERT_NE(it, ref_index.end()) << "entry (" << brows[k] << ", " << bcols[k] << ") not in the expanded pattern";
    EXPECT_EQ(blocks.find(brows[k], bcols[k]), static_cast<std::int64_t>(k));
    EXPECT_EQ(got[k], want[it->second]) << "sum of (" << brows[k] << ", " << bcols[k] << ")";
    ref_index.erase(it);  // each entry once
  }
  EXPECT_TRUE(ref_index.empty());
  // A pass sorted by row with a row hint, as the other forms' entries are looked up: the same
  // answers as without, for held pairs and for misses (rows between and beyond the block rows,
  // unknown columns) mixed in.
  std::vector<std::pair<std::int64_t, std::int64_t>> queries;
  for (std::size_t k = 0; k < brows.size(); ++k) queries.emplace_back(brows[k], bcols[k]);
  std::uniform_int_distribution<std::int64_t> any_dof(0, 3 * 6000);
  for (int k = 0; k < 3000; ++k) queries.emplace_back(any_dof(rng), any_dof(rng));
  std::sort(queries.begin(), queries.end());
  std::size_t hint = 0;
  for (const auto& [row, col] : queries)
    ASSERT_EQ(blocks.find(row, col, &hint), blocks.find(row, col)) << "(" << row << ", " << col << ")";
  // The owned rows' direct lookup (the dense range) against the search of row_nodes alone.
  NodeBlockReduction searched = blocks;
  searched.dense_begin = searched.dense_end = 0;
  for (const auto& [row, col] : queries)
    ASSERT_EQ(searched.find(row, col), blocks.find(row, col)) << "(" << row << ", " << col << ")";
  // Pairs that no block holds: an unknown row node, an unknown column node, a mass-only block's
  // off-diagonal component.
  EXPECT_EQ(blocks.find(3 * 5000, 3 * 1000), -1);
  EXPECT_EQ(blocks.find(3 * c.local_to_global[0], 3 * 99999), -1);
  EXPECT_EQ(blocks.find(-1, 0), -1);
  const auto mass_node = std::find_if(c.mass_nodes.begin(), c.mass_nodes.end(),
                                      [](std::int32_t n) { return n >= 250; });
  ASSERT_NE(mass_node, c.mass_nodes.end());
  const std::int64_t mass_only = c.local_to_global[*mass_node];
  EXPECT_EQ(blocks.find(3 * mass_only, 3 * mass_only + 1), -1);
  EXPECT_GE(blocks.find(3 * mass_only + 1, 3 * mass_only + 1), 0);
}

TEST(NodeBlockReduction, MatchesTheExpandedPatternOwnedRangeInside) {
  expect_matches_expanded(random_case(1), 1200, 1400);
}

TEST(NodeBlockReduction, MatchesTheExpandedPatternAllOwned) { expect_matches_expanded(random_case(2), 1000, 1600); }

TEST(NodeBlockReduction, MatchesTheExpandedPatternNoneOwned) {
  expect_matches_expanded(random_case(3), 5000, 5000);
  expect_matches_expanded(random_case(4), 0, 10);
}

// The reserve of random node pairs (rows inside and outside the owned range, used and unused
// nodes, repeats): each requested pair's entries that neither the blocks nor the fixed part hold,
// numbered on from the first entry in pair order, found through the owned rows' direct index and
// through the search alike; nothing for pairs not requested.
TEST(ReservedBlocks, HoldsTheRequestedEntriesNothingElseHolds) {
  const Case c = random_case(7);
  const NodeBlockReduction blocks =
      NodeBlockReduction::build({{{static_cast<int>(c.elastic_nodes.size() / 8), c.elastic_nodes.data(),
                                   c.local_to_global.data(), ElementLayout::elastic},
                                  0},
                                 {{static_cast<int>(c.mass_nodes.size() / 8), c.mass_nodes.data(),
                                   c.local_to_global.data(), ElementLayout::consistent_mass},
                                  0}},
                                1200, 1400);
  ASSERT_GT(blocks.dense_end, blocks.dense_begin);
  std::mt19937_64 rng(11);
  std::uniform_int_distribution<std::int64_t> node(990, 1610);
  std::vector<ReservedBlocks::NodePair> pairs;
  for (int k = 0; k < 3000; ++k) pairs.push_back({node(rng), node(rng)});
  for (int k = 0; k < 300; ++k) pairs.push_back(pairs[static_cast<std::size_t>(k) * 7]);  // repeats
  std::vector<ReservedBlocks::NodePair> requested = pairs;
  std::sort(requested.begin(), requested.end());
  requested.erase(std::unique(requested.begin(), requested.end()), requested.end());
  // The fixed part holds some diagonal entries.
  const auto held = [](PetscInt row, PetscInt col) { return row == col && row % 7 == 0; };
  const std::size_t first = 100;
  ReservedBlocks reserve;
  reserve.build(pairs, blocks, held, first);

  std::size_t next = first, with_entries = 0;
  for (const auto& [row, col] : requested) {
    const std::int64_t k = blocks.find_block(row, col);
    unsigned missing = 0x1ffu & ~(k >= 0 ? static_cast<unsigned>(blocks.block_mask[static_cast<std::size_t>(k)]) : 0u);
    for (int bit = 0; bit < 9; ++bit)
      if (held(static_cast<PetscInt>(3 * row + bit / 3), static_cast<PetscInt>(3 * col + bit % 3)))
        missing &= ~(1u << bit);
    const ReservedBlocks::Block b = reserve.find_block(row, col);
    ASSERT_EQ(b.mask, missing) << "(" << row << ", " << col << ")";
    if (!missing) continue;
    EXPECT_EQ(b.start, next) << "(" << row << ", " << col << ")";
    next += kBlockMaskBits[missing];
    ++with_entries;
  }
  EXPECT_GT(with_entries, 100u) << "the case reserves too little to test";
  EXPECT_EQ(reserve.num_entries(), next - first);
  for (int k = 0; k < 3000; ++k) {
    const ReservedBlocks::NodePair p{node(rng), node(rng)};
    if (!std::binary_search(requested.begin(), requested.end(), p)) {
      ASSERT_EQ(reserve.find_block(p[0], p[1]).mask, 0u) << "(" << p[0] << ", " << p[1] << ")";
    }
  }
  std::vector<PetscInt> rows, cols;
  reserve.entries(&rows, &cols);
  ASSERT_EQ(rows.size(), reserve.num_entries());
  for (std::size_t e = 0; e < rows.size(); ++e) {
    const ReservedBlocks::Block b = reserve.find_block(rows[e] / 3, cols[e] / 3);
    const int bit = static_cast<int>(3 * (rows[e] % 3) + cols[e] % 3);
    ASSERT_TRUE(b.mask >> bit & 1u);
    EXPECT_EQ(b.start + static_cast<std::size_t>(entry_in_block(b.mask, bit)), first + e);
  }
}

TEST(NodeBlockReduction, EmptyForms) {
  const std::vector<std::int64_t> l2g = {0};
  const NodeBlockReduction r = NodeBlockReduction::build({{{0, nullptr, l2g.data(), ElementLayout::elastic}, 0}}, 0,
                                                         10);
  EXPECT_EQ(r.num_blocks(), 0u);
  EXPECT_EQ(r.num_entries(), 0u);
  EXPECT_EQ(r.find(0, 0), -1);
  std::vector<PetscInt> rows, cols;
  r.entries(&rows, &cols);
  EXPECT_TRUE(rows.empty());
}

TEST(NodeBlockReduction, RepeatedBuildsGiveTheSameMap) {
  const Case c = random_case(9);
  const auto build = [&] {
    return NodeBlockReduction::build({{{static_cast<int>(c.elastic_nodes.size() / 8), c.elastic_nodes.data(),
                                        c.local_to_global.data(), ElementLayout::elastic},
                                       0}},
                                     1100, 1300);
  };
  const NodeBlockReduction a = build(), b = build();
  EXPECT_EQ(a.block_col, b.block_col);
  EXPECT_EQ(a.block_mask, b.block_mask);
  EXPECT_EQ(a.block_start, b.block_start);
  EXPECT_EQ(a.forms[0].offsets, b.forms[0].offsets);
  EXPECT_EQ(a.forms[0].sources, b.forms[0].sources);
  // Sources ascend within each block: the fixed summation order.
  for (std::size_t k = 0; k < a.num_blocks(); ++k)
    EXPECT_TRUE(std::is_sorted(a.forms[0].sources.begin() + a.forms[0].offsets[k],
                               a.forms[0].sources.begin() + a.forms[0].offsets[k + 1]));
}

// The host's chunked sums (index_elements, add_elements over uneven chunks, forms in order) give
// reduce()'s bits.
TEST(NodeBlockReduction, ChunkedSumsEqualReduceBitForBit) {
  const Case c = random_case(10);
  const int ne = static_cast<int>(c.elastic_nodes.size() / 8), nm = static_cast<int>(c.mass_nodes.size() / 8);
  const std::size_t elastic_raw = kElasticCooPerElement * static_cast<std::size_t>(ne);
  NodeBlockReduction r = NodeBlockReduction::build(
      {{{ne, c.elastic_nodes.data(), c.local_to_global.data(), ElementLayout::elastic}, 0},
       {{nm, c.mass_nodes.data(), c.local_to_global.data(), ElementLayout::consistent_mass}, elastic_raw}},
      1100, 1400);
  std::mt19937_64 rng(6);
  std::uniform_real_distribution<double> mantissa(-1, 1), exponent(-12, 12);
  std::vector<double> raw(elastic_raw + kMassCooPerElement * static_cast<std::size_t>(nm));
  for (double& v : raw) v = mantissa(rng) * std::pow(10.0, exponent(rng));
  std::vector<double> want(r.num_entries());
  r.reduce(raw.data(), want.data());

  r.index_elements();
  EXPECT_TRUE(r.forms[0].sources.empty());
  std::vector<double> got(r.num_entries(), 0.0);
  for (std::size_t m = 0; m < 2; ++m) {
    const int count = m == 0 ? ne : nm;
    const int per = m == 0 ? kElasticCooPerElement : kMassCooPerElement;
    for (int first = 0; first < count; first += 37) {
      const int n = std::min(37, count - first);
      r.add_elements(m, first, n, raw.data() + r.forms[m].raw_begin + static_cast<std::size_t>(per) * first,
                     got.data());
    }
  }
  ASSERT_EQ(got.size(), want.size());
  for (std::size_t k = 0; k < want.size(); ++k) ASSERT_EQ(got[k], want[k]) << "entry " << k;
}

TEST(NodeBlockReduction, TooManyElementsForThe32BitMapIsAClearError) {
  const std::vector<std::int64_t> l2g = {0};
  try {
    NodeBlockReduction::build({{{1 << 26, nullptr, l2g.data(), ElementLayout::elastic}, 0}}, 0, 1);
    FAIL() << "no error";
  } catch (const std::length_error& e) {
    EXPECT_NE(std::string(e.what()).find("more ranks"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace dipc
