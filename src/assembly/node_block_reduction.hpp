// NodeBlockReduction: the Hessian entries of the element forms as distinct node blocks, and the
// map that sums the forms' element values into them.
//
// An element form's Hessian is a dense block over each hex's 8x8 node pairs. Expanded to scalar
// COO entries it is 576 (row, col) pairs per hex, each repeated in up to 8 elements; building,
// reducing and storing that list was most of the setup's time and memory (docs/performance.md).
// Here a rank keeps one entry per distinct node pair (row node, col node) — a block of up to 9
// scalar entries — and, per element form, the list of the element node pairs (e, a, b) that
// fall on each block (64 per element, 4 B each). Where a value lies among the form's raw
// values follows from (e, a, b, i, j) and the form's ElementLayout, so no per-entry index is
// stored. Each entry sums, from 0, the forms in their order, each over its elements in
// ascending order: the same order on the host and on the device, so both give the same bits.
#pragma once
#include <petscsys.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "assembly/cuda/node_block_pattern.hpp"
#include "assembly/element_pattern.hpp"
#include "assembly/large_page_vector.hpp"

namespace dipc {

// The number of set bits of each 9-bit block mask. A table, because without -mpopcnt (dipc
// builds for any x86-64) __builtin_popcount is a library call, and it runs for every entry.
inline constexpr auto kBlockMaskBits = [] {
  std::array<std::uint8_t, 512> bits{};
  for (unsigned m = 0; m < 512; ++m)
    for (int b = 0; b < 9; ++b) bits[m] = static_cast<std::uint8_t>(bits[m] + (m >> b & 1u));
  return bits;
}();
// Where entry bit (3i + j) of a block with `mask` lies among the block's entries.
inline int entry_in_block(unsigned mask, int bit) { return kBlockMaskBits[mask & ((1u << bit) - 1u)]; }

class NodeBlockReduction {
 public:
  // One element form's pattern, and where its values start in the raw value array.
  struct Input {
    ElementPattern pattern;
    std::size_t raw_begin = 0;
  };
  // An element form's map: the sources of block k are sources[offsets[k] .. offsets[k+1]),
  // each 64e + 8a + b (element e, row node a, col node b), ascending.
  struct FormMap {
    ElementLayout layout = ElementLayout::elastic;
    std::size_t raw_begin = 0;
    LargePageVector<std::uint32_t> offsets, sources;
    LargePageVector<std::uint32_t> block_of;  // after index_elements(): the block of 64e + 8a + b
  };

  // The distinct blocks of the forms' patterns on a rank that owns the global nodes
  // [owned_begin, owned_end): those rows are bucketed directly, the few others (ghost nodes)
  // after sorting them. Throws std::length_error when a form has 2^26 elements or more (its
  // sources would not fit 32 bits; run on more ranks).
  static NodeBlockReduction build(const std::vector<Input>& forms, std::int64_t owned_begin, std::int64_t owned_end);
  // build() on the device (device::build_node_blocks), the same result bit for bit: the pattern
  // (row_nodes .. block_start) on the host, and in *on_device the block masks and starts and the
  // forms' offsets and sources, of which the host keeps none (forms[f].offsets and .sources stay
  // empty). Throws device::DeviceError where the build or the machine has no CUDA.
  static NodeBlockReduction build_on_device(const std::vector<Input>& forms, std::int64_t owned_begin,
                                            std::int64_t owned_end, device::NodeBlocks* on_device);

  std::size_t num_blocks() const { return block_col.size(); }
  // block_start in 32 bits, as the device keeps it (4 B per block instead of 8). Throws
  // std::length_error when the rank has 2^32 entries or more (run on more ranks).
  std::vector<std::uint32_t> block_start_32() const;
  // row_start and block_col in 32 bits, as the device keeps them. Throw std::length_error when a
  // rank has 2^32 blocks or a column node id is 2^32 or more (run on more ranks).
  std::vector<std::uint32_t> row_start_32() const;
  std::vector<std::uint32_t> block_col_32() const;
  // Scalar entries of all blocks; entries are numbered block by block, bits 3i + j ascending.
  std::size_t num_entries() const { return block_start.empty() ? 0 : static_cast<std::size_t>(block_start.back()); }
  // Global dof ids of every entry, in entry order (3 node + i, 3 node + j). Throws
  // std::overflow_error when an id does not fit PetscInt (configure PETSc with 64-bit indices).
  void entries(std::vector<PetscInt>* rows, std::vector<PetscInt>* cols) const;
  // f(entry, row, col) for each entry of block k, whose row node is row_node, in entry order
  // (bits 3i + j ascending); row and col are global dof ids 3 node + component.
  template <class F>
  void for_each_entry(std::int64_t row_node, std::size_t k, F&& f) const {
    std::size_t entry = block_start[k];
    for (int bit = 0; bit < 9; ++bit)
      if (block_mask[k] >> bit & 1u) f(entry++, 3 * row_node + bit / 3, 3 * block_col[k] + bit % 3);
  }
  // Entry index of the dof pair (row, col), or -1 where no block holds it. With row_hint, the
  // search for the row starts at block row *row_hint and leaves there the block row it ended
  // at: a pass over pairs sorted by row (start with 0) then finds each row in a step or two
  // instead of a binary search (3M lumped-mass diagonal entries at 1M hexes took 0.25 s so).
  std::int64_t find(std::int64_t row, std::int64_t col, std::size_t* row_hint = nullptr) const;
  // The block row of row_node, or -1; row_hint as for find().
  std::int64_t find_row(std::int64_t row_node, std::size_t* row_hint = nullptr) const;
  // The block of the node pair (row_node, col_node), or -1; row_hint as for find().
  std::int64_t find_block(std::int64_t row_node, std::int64_t col_node, std::size_t* row_hint = nullptr) const;
  // unique[k], k < num_entries(), from the raw values of the forms (written in their layouts).
  void reduce(const double* raw, double* unique) const;

  // The inverse map, for sums on the host element chunk by chunk: fills each form's block_of
  // and frees its offsets and sources (reduce() then no longer works). Throws std::length_error
  // when the blocks do not fit 32-bit ids.
  void index_elements();
  // Adds the values of form m's elements [first, first + count) (in its layout, element first's
  // at values) into unique. Called for the forms in order and their elements in ascending order
  // on zeroed entries, it gives reduce()'s sums bit for bit: each entry receives the same terms
  // in the same order.
  void add_elements(std::size_t m, int first, int count, const double* values, double* unique) const;

  std::vector<std::int64_t> row_nodes;  // global node of each block row, ascending
  // The owned nodes [dense_begin, dense_end) are rows dense_below + (node - dense_begin), found
  // without a search: the contact pattern's lookups (16 node blocks per pair, hundreds of
  // thousands of pairs per pattern change) spent most of their time in binary searches of
  // row_nodes. Other rows (ghost nodes) are searched.
  std::int64_t dense_begin = 0, dense_end = 0;
  std::size_t dense_below = 0;
  std::vector<std::size_t> row_start;          // blocks of row r: [row_start[r], row_start[r+1])
  LargePageVector<std::int64_t> block_col;     // global column node of each block, ascending in a row
  LargePageVector<std::uint16_t> block_mask;   // which of the block's 9 entries exist (bit 3i + j)
  LargePageVector<std::uint64_t> block_start;  // first entry of each block; num_blocks() + 1
  std::vector<FormMap> forms;                  // in the order of build()'s inputs
  // Distinct for every NodeBlockReduction made (a copy keeps its original's): DirectMatrix keeps
  // its device copy of the blocks across new matrices while the id it copied holds.
  std::uint64_t id = next_id();

 private:
  static std::uint64_t next_id();
};

}  // namespace dipc
