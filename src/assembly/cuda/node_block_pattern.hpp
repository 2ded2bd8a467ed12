// The node-block pattern of the element forms (NodeBlockReduction, nonlinear/) built on the
// device: the distinct (row node, column node) blocks of every form's 8x8 element node pairs,
// each block's entry mask and first entry, and per form the element node pairs that fall on
// each block. At 1M hexes that is sorting 64M element node pairs, which took one host core
// 2.2 s of the 1M-hex GPU setup (docs/performance.md, "Setup"); the device sorts them with a
// radix sort in milliseconds.
//
// The result is the host build's, bit for bit: a stable sort of the pairs by (row, column),
// generated in the order form, element, row node, column node, keeps each block's pairs in the
// summation order NodeBlockReduction documents.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "assembly/element_loops.hpp"
#include "device/device_runtime.hpp"

namespace dipc::device {

// One element form: the row slot (see build_node_blocks) of each of its elements' 8 nodes, in
// device memory, and the layout that says which entries of a block it writes.
struct NodeBlockForm {
  const std::uint32_t* d_slots = nullptr;  // 8 per element
  std::size_t num_elements = 0;
  ElementLayout layout = ElementLayout::elastic;
};

// The pattern, in device memory except for num_blocks.
struct NodeBlocks {
  std::size_t num_blocks = 0;
  Array<std::uint64_t> row_start{"node-block row starts"};  // num_rows + 1: blocks of row r
  Array<std::int64_t> col{"node-block columns"};            // global column node of each block
  Array<std::uint16_t> mask{"node-block masks"};            // entries present, bit 3i + j
  Array<std::uint64_t> start{"node-block starts"};          // first entry; num_blocks + 1
  // Per form: its pairs 64e + 8a + b of block k are sources[offsets[k] .. offsets[k+1]).
  std::vector<Array<std::uint32_t>> offsets, sources;
};

// Rows and columns are numbered by slots 0 .. num_rows - 1 that follow the global node order;
// slot_nodes (device) gives each slot's global node. The forms' pairs must number fewer than
// 2^32 together. Every pair (a, b) of an element is a pair of its nodes' slots.
void build_node_blocks(const NodeBlockForm* forms, int num_forms, std::size_t num_rows,
                       const std::int64_t* d_slot_nodes, NodeBlocks* out);

}  // namespace dipc::device
