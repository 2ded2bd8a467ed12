// device::reduce_coo against CooReduction::reduce on a random element-like pattern, and
// device::reduce_element_blocks against NodeBlockReduction::reduce on random elements of an
// elastic and a consistent-mass layout: the same sums in the same order, so the same bits, also
// summed element chunk by chunk (add_element_block_chunk); the
// node-block pattern built on the device against the host build, array for array; the
// Hessian's other device steps (add_at, eliminate) against their host loops; TargetPart's
// device sums (values sorted by target) against its host loop, also after a repeated
// keep_on_device(), and its lookups on the device against the host's. Skips where no GPU is
// present.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>
#include <random>
#include <stdexcept>
#include <vector>

#include "assembly/block_entries.hpp"
#include "assembly/coo_reduction.hpp"
#include "assembly/cuda/element_kernels.hpp"
#include "assembly/element_block_part.hpp"
#include "assembly/node_block_reduction.hpp"
#include "assembly/reserved_blocks.hpp"
#include "assembly/target_part.hpp"
#include "device/device_runtime.hpp"

namespace dipc {
namespace {

TEST(TargetPartGpu, DeviceSumsEqualHostSumsBitForBit) {
  if (device::device_count() == 0) GTEST_SKIP() << "no CUDA device";
  // Groups of 1 to 4 of 600 nodes onto 5000 matrix entries: a node block's entries are
  // 9 (row node + col node) mod 5000 onward, so that many values land on each entry and the
  // groups' blocks overlap; some entries start non-zero; values over many magnitudes, so that
  // another order would show.
  std::mt19937_64 rng(5);
  std::uniform_int_distribution<std::int64_t> node(0, 599);
  std::uniform_int_distribution<int> size(1, 4);
  std::uniform_real_distribution<double> mantissa(-1, 1), exponent(-12, 12);
  std::vector<NodeGroup> groups(20000);
  std::size_t n = 0;
  for (NodeGroup& g : groups) {
    g.count = size(rng);
    for (int a = 0; a < g.count; ++a) g.node[a] = node(rng);
    n += node_group_values(g.count);
  }
  std::vector<double> raw(n), start(5000);
  for (double& v : raw) v = mantissa(rng) * std::pow(10.0, exponent(rng));
  for (double& v : start) v = mantissa(rng);
  TargetPart part;
  ASSERT_EQ(part.build(groups,
                       [](std::int64_t row_node, std::int64_t col_node, std::size_t*, std::int64_t entry[9]) {
                         for (int bit = 0; bit < 9; ++bit) entry[bit] = (9 * (row_node + col_node) + bit) % 5000;
                       }),
            0u);
  std::vector<double> host = start;
  part.add(raw.data(), host.data());
  device::Array<double> d_raw("raw"), d_values("values");
  d_raw.upload(raw);
  d_values.upload(start);
  part.keep_on_device();
  // A second call keeps the targets: on several ranks, a rank whose own contact pattern kept
  // still while another's changed went through it again, and sorted an empty upload.
  part.keep_on_device();
  part.add_on_device(d_raw.data(), d_values.data());
  std::vector<double> device_values(start.size());
  d_values.download(device_values.data());
  EXPECT_EQ(std::memcmp(host.data(), device_values.data(), host.size() * sizeof(double)), 0);
}

TEST(CooReductionGpu, DeviceSumsEqualHostSumsBitForBit) {
  if (device::device_count() == 0) GTEST_SKIP() << "no CUDA device";
  std::mt19937_64 rng(11);
  const PetscInt owned_begin = 3000, owned_end = 9000;
  std::uniform_int_distribution<PetscInt> owned(owned_begin, owned_end - 1), any(0, 12000);
  std::uniform_int_distribution<int> pick(0, 19);
  std::vector<PetscInt> rows, cols;
  for (int block = 0; block < 3000; ++block) {
    PetscInt dofs[24];
    for (PetscInt& d : dofs) d = pick(rng) == 0 ? any(rng) : owned(rng);
    for (PetscInt r : dofs)
      for (PetscInt c : dofs) rows.push_back(r), cols.push_back(pick(rng) == 0 && pick(rng) == 0 ? -1 : c);
  }
  const CooReduction reduction = CooReduction::build(rows.data(), cols.data(), rows.size(), owned_begin, owned_end);
  // Values over many magnitudes, so that a different summation order would change the bits.
  std::uniform_real_distribution<double> mantissa(-1, 1), exponent(-12, 12);
  std::vector<double> raw(rows.size());
  for (double& v : raw) v = mantissa(rng) * std::pow(10.0, exponent(rng));
  std::vector<double> host(reduction.num_unique());
  reduction.reduce(raw.data(), host.data());

  device::Array<double> d_raw("raw"), d_unique("unique");
  device::Array<CooReduction::Index> d_offsets("offsets"), d_sources("sources");
  d_raw.upload(raw);
  d_offsets.upload(reduction.offsets);
  d_sources.upload(reduction.sources);
  d_unique.resize(reduction.num_unique());
  device::reduce_coo(d_raw.data(), d_offsets.data(), d_sources.data(), reduction.num_unique(), d_unique.data());
  const std::vector<double> device_sums = d_unique.to_host();
  ASSERT_EQ(device_sums.size(), host.size());
  ASSERT_GT(host.size(), 0u);
  EXPECT_EQ(std::memcmp(device_sums.data(), host.data(), host.size() * sizeof(double)), 0);
  for (std::size_t u = 0; u < host.size(); ++u) ASSERT_EQ(device_sums[u], host[u]) << "unique entry " << u;
}

// Values over many magnitudes, so that a different summation order would change the bits.
std::vector<double> spread_values(std::mt19937_64& rng, std::size_t n) {
  std::uniform_real_distribution<double> mantissa(-1, 1), exponent(-12, 12);
  std::vector<double> v(n);
  for (double& x : v) x = mantissa(rng) * std::pow(10.0, exponent(rng));
  return v;
}

// Local nodes 0 .. n - 1 numbered globally from 500 on, shuffled.
std::vector<std::int64_t> shuffled_global_ids(std::mt19937_64& rng, int n) {
  std::vector<std::int64_t> l2g(static_cast<std::size_t>(n));
  std::iota(l2g.begin(), l2g.end(), 500);
  std::shuffle(l2g.begin(), l2g.end(), rng);
  return l2g;
}

// `count` elements of 8 distinct local nodes drawn from [first, first + span).
std::vector<std::int32_t> random_elements(std::mt19937_64& rng, int count, int first, int span) {
  std::vector<std::int32_t> pool(static_cast<std::size_t>(span)), nodes;
  std::iota(pool.begin(), pool.end(), first);
  for (int e = 0; e < count; ++e) {
    std::shuffle(pool.begin(), pool.end(), rng);
    nodes.insert(nodes.end(), pool.begin(), pool.begin() + 8);
  }
  return nodes;
}

// Two element forms on a rank owning nodes [1000, 2500): elastic elements over nodes [0, 2500)
// and consistent-mass elements over [2000, 3000), so that some blocks hold the mass's diagonal
// only; their values behind 7 values of something else, as in the potential's raw array; and
// the host's sums of them.
struct TwoFormSums {
  explicit TwoFormSums(std::uint64_t seed) : rng(seed) {
    l2g = shuffled_global_ids(rng, 3000);
    elastic = random_elements(rng, 2000, 0, 2500);
    mass = random_elements(rng, 600, 2000, 1000);
    const std::size_t elastic_raw = kElasticCooPerElement * elastic.size() / 8;
    const std::size_t mass_raw = kMassCooPerElement * mass.size() / 8;
    blocks = NodeBlockReduction::build(
        {{{static_cast<int>(elastic.size() / 8), elastic.data(), l2g.data(), ElementLayout::elastic}, 7},
         {{static_cast<int>(mass.size() / 8), mass.data(), l2g.data(), ElementLayout::consistent_mass},
          7 + elastic_raw}},
        1000, 2500);
    raw = spread_values(rng, 7 + elastic_raw + mass_raw);
    host.resize(blocks.num_entries());
    blocks.reduce(raw.data(), host.data());
  }
  std::mt19937_64 rng;
  std::vector<std::int64_t> l2g;
  std::vector<std::int32_t> elastic, mass;
  NodeBlockReduction blocks;
  std::vector<double> raw, host;
};

TEST(CooReductionGpu, NodeBlockSumsEqualHostSumsBitForBit) {
  if (device::device_count() == 0) GTEST_SKIP() << "no CUDA device";
  const TwoFormSums sums(12);
  const NodeBlockReduction& blocks = sums.blocks;
  const std::vector<double>& raw = sums.raw;
  const std::vector<double>& host = sums.host;

  device::Array<double> d_raw("raw"), d_unique("unique");
  device::Array<std::uint16_t> d_mask("mask");
  device::Array<std::uint32_t> d_start("start");
  device::Array<std::uint32_t> d_off0("offsets"), d_src0("sources"), d_off1("offsets"), d_src1("sources");
  d_raw.upload(raw);
  d_mask.upload(blocks.block_mask);
  d_start.upload(blocks.block_start_32());
  d_off0.upload(blocks.forms[0].offsets);
  d_src0.upload(blocks.forms[0].sources);
  d_off1.upload(blocks.forms[1].offsets);
  d_src1.upload(blocks.forms[1].sources);
  const device::ElementBlockMap maps[2] = {{ElementLayout::elastic, blocks.forms[0].raw_begin, d_off0.data(),
                                            d_src0.data()},
                                           {ElementLayout::consistent_mass, blocks.forms[1].raw_begin, d_off1.data(),
                                            d_src1.data()}};
  d_unique.resize(blocks.num_entries());
  device::reduce_element_blocks(d_raw.data(), blocks.num_blocks(), d_mask.data(), d_start.data(), maps, 2,
                                d_unique.data());
  const std::vector<double> device_sums = d_unique.to_host();
  ASSERT_EQ(device_sums.size(), host.size());
  ASSERT_GT(host.size(), 0u);
  EXPECT_EQ(std::memcmp(device_sums.data(), host.data(), host.size() * sizeof(double)), 0);
  for (std::size_t k = 0; k < host.size(); ++k) ASSERT_EQ(device_sums[k], host[k]) << "entry " << k;
}

// The element sums chunk by chunk (device::add_element_block_chunk over the blocks that
// element_chunk_block_ranges gives each chunk), form after form, onto entries from 0: the whole
// reduction's bits, for chunks of one element, of a few, and of all.
TEST(CooReductionGpu, NodeBlockSumsChunkByChunkEqualTheWholeSumsBitForBit) {
  if (device::device_count() == 0) GTEST_SKIP() << "no CUDA device";
  const TwoFormSums sums(13);
  const NodeBlockReduction& blocks = sums.blocks;
  const std::vector<double>& raw = sums.raw;
  const std::vector<double>& host = sums.host;
  ASSERT_GT(host.size(), 0u);

  device::Array<double> d_chunk("chunk"), d_unique("unique");
  device::Array<std::uint16_t> d_mask("mask");
  device::Array<std::uint32_t> d_start("start");
  d_mask.upload(blocks.block_mask);
  d_start.upload(blocks.block_start_32());
  std::vector<device::Array<std::uint32_t>> d_off, d_src;
  std::vector<device::ElementBlockMap> maps;
  for (const auto& form : blocks.forms) {
    d_off.emplace_back("offsets");
    d_off.back().upload(form.offsets);
    d_src.emplace_back("sources");
    d_src.back().upload(form.sources);
  }
  for (std::size_t m = 0; m < blocks.forms.size(); ++m)
    maps.push_back({blocks.forms[m].layout, blocks.forms[m].raw_begin, d_off[m].data(), d_src[m].data()});
  const std::size_t num_elements[2] = {sums.elastic.size() / 8, sums.mass.size() / 8};
  for (const std::size_t chunk : {std::size_t{1}, std::size_t{7}, std::size_t{300}, std::size_t{5000}}) {
    d_unique.resize(blocks.num_entries());
    d_unique.set_zero();
    for (std::size_t m = 0; m < maps.size(); ++m) {
      const std::size_t per = element_values(maps[m].layout), size = std::min(chunk, num_elements[m]);
      const std::size_t num_chunks = (num_elements[m] + size - 1) / size;
      std::vector<std::uint64_t> begin, end;
      device::element_chunk_block_ranges(blocks.num_blocks(), maps[m], static_cast<std::uint32_t>(size), num_chunks,
                                         &begin, &end);
      ASSERT_EQ(begin.size(), num_chunks);
      for (std::size_t c = 0; c < num_chunks; ++c) {
        const std::size_t first = c * size, count = std::min(size, num_elements[m] - first);
        d_chunk.upload(raw.data() + maps[m].raw_begin + per * first, per * count);
        device::add_element_block_chunk(d_chunk.data(), static_cast<std::uint32_t>(first),
                                        static_cast<std::uint32_t>(count), begin[c], end[c], d_mask.data(),
                                        d_start.data(), maps[m], d_unique.data());
      }
    }
    const std::vector<double> chunked = d_unique.to_host();
    ASSERT_EQ(chunked.size(), host.size());
    EXPECT_EQ(std::memcmp(chunked.data(), host.data(), host.size() * sizeof(double)), 0) << "chunks of " << chunk;
  }
}

// NodeBlockReduction::build_on_device against build(): two forms (elastic, and consistent mass
// whose blocks hold the diagonal only) or the elastic one alone (the device's one-form path),
// ghost nodes on both sides of the owned range and owned nodes of no element (empty rows).
void expect_device_build_equals_host_build(bool with_mass) {
  std::mt19937_64 rng(14);
  const std::vector<std::int64_t> l2g = shuffled_global_ids(rng, 3000);
  const std::vector<std::int32_t> elastic = random_elements(rng, 2000, 0, 2500);
  const std::vector<std::int32_t> mass = random_elements(rng, 600, 2000, 1000);
  std::vector<NodeBlockReduction::Input> inputs = {
      {{static_cast<int>(elastic.size() / 8), elastic.data(), l2g.data(), ElementLayout::elastic}, 7}};
  if (with_mass)
    inputs.push_back(
        {{static_cast<int>(mass.size() / 8), mass.data(), l2g.data(), ElementLayout::consistent_mass}, 99});
  // Owned nodes [300, 2500): those below 500 are in no element.
  const NodeBlockReduction host = NodeBlockReduction::build(inputs, 300, 2500);
  device::NodeBlocks on_device;
  const NodeBlockReduction dev = NodeBlockReduction::build_on_device(inputs, 300, 2500, &on_device);
  ASSERT_GT(host.num_blocks(), 0u);
  EXPECT_EQ(dev.row_nodes, host.row_nodes);
  EXPECT_EQ(dev.row_start, host.row_start);
  EXPECT_TRUE(dev.block_col == host.block_col);
  EXPECT_TRUE(dev.block_mask == host.block_mask);
  EXPECT_TRUE(dev.block_start == host.block_start);
  EXPECT_EQ(on_device.num_blocks, host.num_blocks());
  EXPECT_TRUE(on_device.mask.to_host() == std::vector<std::uint16_t>(host.block_mask.begin(), host.block_mask.end()));
  EXPECT_TRUE(on_device.start.to_host() ==
              std::vector<std::uint64_t>(host.block_start.begin(), host.block_start.end()));
  ASSERT_EQ(dev.forms.size(), host.forms.size());
  ASSERT_EQ(on_device.offsets.size(), host.forms.size());
  for (std::size_t f = 0; f < host.forms.size(); ++f) {
    EXPECT_EQ(dev.forms[f].layout, host.forms[f].layout);
    EXPECT_EQ(dev.forms[f].raw_begin, host.forms[f].raw_begin);
    EXPECT_TRUE(dev.forms[f].sources.empty());
    EXPECT_TRUE(on_device.offsets[f].to_host() ==
                std::vector<std::uint32_t>(host.forms[f].offsets.begin(), host.forms[f].offsets.end()))
        << "form " << f;
    EXPECT_TRUE(on_device.sources[f].to_host() ==
                std::vector<std::uint32_t>(host.forms[f].sources.begin(), host.forms[f].sources.end()))
        << "form " << f;
  }
}

TEST(CooReductionGpu, NodeBlocksBuiltOnTheDeviceEqualTheHostBuild) {
  if (device::device_count() == 0) GTEST_SKIP() << "no CUDA device";
  expect_device_build_equals_host_build(true);
}

TEST(CooReductionGpu, OneFormsNodeBlocksBuiltOnTheDeviceEqualTheHostBuild) {
  if (device::device_count() == 0) GTEST_SKIP() << "no CUDA device";
  expect_device_build_equals_host_build(false);
}

// TargetPart's lookups on the device (build_on_device over group_targets.hpp's index) against
// its host lookups (BlockEntries), and the reserve found on the device against the host's
// build: element blocks of two forms (the consistent mass's hold only
// their diagonals, so a reserve completes some element blocks), owned rows found directly and
// ghost rows searched, nodes of no row, a reserve of half the groups' blocks and fixed extra
// entries. The other half misses entries: both count the same. The half that fits gets the same
// targets: its values summed through either give the same bits.
TEST(TargetPartGpu, DeviceLookupsEqualHostLookups) {
  if (device::device_count() == 0) GTEST_SKIP() << "no CUDA device";
  std::mt19937_64 rng(21);
  const std::vector<std::int64_t> l2g = shuffled_global_ids(rng, 3000);
  const std::vector<std::int32_t> elastic = random_elements(rng, 1500, 0, 2500);
  const std::vector<std::int32_t> mass = random_elements(rng, 600, 2000, 1000);
  ElementBlockPart elements;
  ASSERT_EQ(elements.build(
                {{{static_cast<int>(elastic.size() / 8), elastic.data(), l2g.data(), ElementLayout::elastic}, 0},
                 {{static_cast<int>(mass.size() / 8), mass.data(), l2g.data(), ElementLayout::consistent_mass}, 0}},
                true, false, 300, 2500),
            0);
  const NodeBlockReduction& blocks = elements.blocks();
  // Global nodes 450 .. 3549: those below 500 and from 3500 on have no row.
  std::uniform_int_distribution<std::int64_t> node(450, 3549);
  std::uniform_int_distribution<int> size(1, 4);
  std::vector<NodeGroup> groups(6000);
  for (NodeGroup& g : groups) {
    g.count = size(rng);
    for (int a = 0; a < g.count; ++a) g.node[a] = node(rng);
  }
  // Fixed extras: every seventh dof's diagonal that no block holds.
  std::vector<PetscInt> extra_rows, extra_cols;
  for (PetscInt d = 3 * 450; d < 3 * 3550; ++d)
    if (d % 7 == 0 && blocks.find(d, d) < 0) extra_rows.push_back(d), extra_cols.push_back(d);
  ASSERT_GT(extra_rows.size(), 10u);
  const std::vector<NodeGroup> fitting(groups.begin(), groups.begin() + 3000);
  std::vector<ReservedBlocks::NodePair> pairs;
  for (const NodeGroup& g : fitting)
    for (int a = 0; a < g.count; ++a)
      for (int b = 0; b < g.count; ++b) pairs.push_back({g.node[a], g.node[b]});
  ReservedBlocks reserve;
  const BlockEntries entries{&blocks, &reserve, &extra_rows, &extra_cols};
  reserve.build(
      pairs, blocks, [&](PetscInt row, PetscInt col) { return entries.find_extra(row, col) >= 0; },
      blocks.num_entries() + extra_rows.size());
  ASSERT_GT(reserve.num_entries(), 100u);
  reserve.upload();
  device::Array<std::int64_t> d_extra_rows("extra rows"), d_extra_cols("extra columns");
  d_extra_rows.upload(std::vector<std::int64_t>(extra_rows.begin(), extra_rows.end()));
  d_extra_cols.upload(std::vector<std::int64_t>(extra_cols.begin(), extra_cols.end()));
  device::BlockEntryIndex index;
  ASSERT_TRUE(elements.device_index(&index));
  ASSERT_TRUE(reserve.device_index(&index));
  index.num_extra = extra_rows.size();
  index.extra_row = d_extra_rows.data(), index.extra_col = d_extra_cols.data();
  index.extra_first = static_cast<std::uint32_t>(blocks.num_entries());
  const std::size_t num_entries = blocks.num_entries() + extra_rows.size() + reserve.num_entries();

  // The reserve found on the device: the host build's blocks, masks and entries.
  std::vector<std::int64_t> rows, cols;
  std::vector<std::uint16_t> masks;
  device::reserve_node_groups(node_group_views(fitting), fitting.size(), index, &rows, &cols, &masks);
  ReservedBlocks device_reserve;
  device_reserve.assign(rows, cols, masks, blocks, reserve.first_entry());
  ASSERT_EQ(device_reserve.num_blocks(), reserve.num_blocks());
  EXPECT_EQ(device_reserve.num_entries(), reserve.num_entries());
  for (std::size_t k = 0; k < reserve.num_blocks(); ++k) {
    ASSERT_EQ(device_reserve.pair(k), reserve.pair(k)) << "block " << k;
    ASSERT_EQ(device_reserve.mask(k), reserve.mask(k)) << "block " << k;
    ASSERT_EQ(device_reserve.start(k), reserve.start(k)) << "block " << k;
  }

  const auto host_find = [&](std::int64_t row_node, std::int64_t col_node, std::size_t* hint, std::int64_t entry[9]) {
    entries.find(row_node, col_node, hint, entry);
  };

  TargetPart host_part, device_part;
  const std::size_t host_missing = host_part.build(groups, host_find);
  EXPECT_GT(host_missing, 0u);
  EXPECT_EQ(device_part.build_on_device(groups, index, num_entries), host_missing);

  ASSERT_EQ(host_part.build(fitting, host_find), 0u);
  ASSERT_EQ(device_part.build_on_device(fitting, index, num_entries), 0u);
  std::size_t n = 0;
  for (const NodeGroup& g : fitting) n += node_group_values(g.count);
  const std::vector<double> raw = spread_values(rng, n), start = spread_values(rng, num_entries);
  std::vector<double> host = start;
  host_part.add(raw.data(), host.data());
  device::Array<double> d_raw("raw"), d_values("values");
  d_raw.upload(raw);
  d_values.upload(start);
  device_part.keep_on_device();
  device_part.add_on_device(d_raw.data(), d_values.data());
  const std::vector<double> got = d_values.to_host();
  ASSERT_EQ(got.size(), host.size());
  EXPECT_EQ(std::memcmp(got.data(), host.data(), host.size() * sizeof(double)), 0);
  EXPECT_THROW(device_part.add(raw.data(), host.data()), std::logic_error);
}

TEST(CooReductionGpu, AddAtAndEliminateEqualTheHostLoops) {
  if (device::device_count() == 0) GTEST_SKIP() << "no CUDA device";
  std::mt19937_64 rng(13);
  const std::size_t n = 5000, fresh_from = 4000;
  std::vector<double> values = spread_values(rng, n);
  // Distinct targets, some among the first fresh_from entries (added onto), some after (set).
  std::vector<std::size_t> index(n);
  std::iota(index.begin(), index.end(), 0);
  std::shuffle(index.begin(), index.end(), rng);
  index.resize(1500);
  const std::vector<double> add = spread_values(rng, index.size());
  std::vector<std::size_t> zero(index.begin(), index.begin() + 300), one(index.begin() + 300, index.begin() + 400);
  std::vector<double> want = values;
  for (std::size_t k = 0; k < index.size(); ++k)
    want[index[k]] = (index[k] < fresh_from ? want[index[k]] : 0.0) + add[k];
  for (std::size_t u : zero) want[u] = 0;
  for (std::size_t u : one) want[u] = 1;

  device::Array<double> d_values("values"), d_add("add");
  device::Array<std::size_t> d_index("index"), d_zero("zero"), d_one("one");
  d_values.upload(values);
  d_add.upload(add);
  d_index.upload(index);
  d_zero.upload(zero);
  d_one.upload(one);
  device::add_at(d_values.data(), d_index.data(), d_add.data(), index.size(), fresh_from);
  device::eliminate(d_values.data(), d_zero.data(), zero.size(), d_one.data(), one.size());
  const std::vector<double> got = d_values.to_host();
  ASSERT_EQ(got.size(), n);
  EXPECT_EQ(std::memcmp(got.data(), want.data(), n * sizeof(double)), 0);
}

}  // namespace
}  // namespace dipc
