// The changing Hessian terms' values (contact and friction pairs, given as node groups) mapped
// onto the matrix's entries on the device: TargetPart's lookups (target_part.hpp) made by one
// thread per group row instead of on the host threads. At 1M hexes on one H200 the host's
// lookups of the stack's 388K pairs (16 node blocks each) were 22 % of the time of 8 contact-rich
// steps (docs/performance.md, "Pattern changes at 8 steps"), and their targets crossed to the
// device after each.
//
// An entry is found as the host finds it (HessianAssembler's BlockEntries): in the element
// forms' node blocks, where the block lacks it in the reserve's blocks, else among the fixed
// part's extra entries; so both give the same targets.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

namespace dipc::device {

// A node group as the assembler's NodeGroup (hessian_pattern.hpp) lays it out in memory (the
// caller checks the layout): a pair's body nodes, the first `count` used.
struct NodeGroupView {
  std::int64_t node[4];
  std::int32_t count;
};

// The matrix's entries, in device memory. Element blocks (NodeBlockReduction): block rows of the
// global nodes row_nodes (ascending), the owned nodes [dense_begin, dense_end) at rows
// dense_below + (node - dense_begin); the blocks of row s are [row_start[s], row_start[s + 1]),
// column node col[k] ascending, entries mask[k] (bit 3i + j) from start[k]. Reserve
// (ReservedBlocks): blocks (reserve_row[k], reserve_col[k]) ascending, those of a dense row node
// from reserve_dense_first[node - dense_begin]; entries reserve_mask[k] from reserve_start[k].
// Fixed part's extra entries: the dof pairs (extra_row[v], extra_col[v]) ascending, entry
// extra_first + v.
struct BlockEntryIndex {
  std::size_t num_rows = 0;
  const std::int64_t* row_nodes = nullptr;
  std::int64_t dense_begin = 0, dense_end = 0;
  std::size_t dense_below = 0;
  const std::uint32_t* row_start = nullptr;
  const std::uint32_t* col = nullptr;
  const std::uint16_t* mask = nullptr;
  const std::uint32_t* start = nullptr;

  std::size_t num_reserved = 0;
  const std::int64_t* reserve_row = nullptr;
  const std::int64_t* reserve_col = nullptr;
  const std::uint16_t* reserve_mask = nullptr;
  const std::uint32_t* reserve_start = nullptr;
  const std::uint32_t* reserve_dense_first = nullptr;  // dense_end - dense_begin + 1

  std::size_t num_extra = 0;
  const std::int64_t* extra_row = nullptr;
  const std::int64_t* extra_col = nullptr;
  std::uint32_t extra_first = 0;
};

// The target entry of every raw value of the groups (device memory; group g's values from
// value_begin[g], laid out as hessian_pattern.hpp says) into targets, `dropped` where the matrix
// has none. Returns how many have none. The entries must number below `dropped`.
std::size_t map_node_groups(const NodeGroupView* groups, const std::uint64_t* value_begin, std::size_t num_groups,
                            const BlockEntryIndex& index, std::uint32_t dropped, std::uint32_t* targets);

// The reserve of the groups' blocks (ReservedBlocks::build, found by a radix sort of the node
// pairs on the device instead of sorts on the host threads): the distinct node pairs (rows[p],
// cols[p]) of each group's nodes whose element block `index` does not hold whole, ascending,
// each with the entries that neither its element block nor the fixed extras hold (masks[p],
// bit 3i + j; 0 where none). `groups` in host memory, their nodes in [0, 2^32); index's
// reserve fields are not read.
void reserve_node_groups(const NodeGroupView* groups, std::size_t num_groups, const BlockEntryIndex& index,
                         std::vector<std::int64_t>* rows, std::vector<std::int64_t>* cols,
                         std::vector<std::uint16_t>* masks);

}  // namespace dipc::device
