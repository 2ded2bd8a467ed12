// ReservedBlocks: matrix entries kept for the Hessian terms whose pattern changes (contact's
// active set, friction's lagged pairs), beyond those the element blocks and the fixed COO
// terms already hold, so that the pattern can change within them without a new matrix.
//
// A change of the contact active set used to make a new matrix: the whole COO part reduced
// again, a new hypre matrix of every entry, and a fresh BoomerAMG setup, once per Newton
// iteration on contact-rich steps (0.54 s of 1.56 s per iteration at 1M hexes on one H200,
// docs/performance.md, "Contact-rich family"). The reserve holds the blocks of the changing
// terms' current patterns, so a shrinking active set can keep the matrix, and with
// -dipc_pattern_remap candidates those of every contact candidate pair (the broad phase's pairs, a
// superset of the active ones along the current Newton segment), so that most changes keep it;
// the reserve's unused entries hold zeros. A pattern outside the reserve makes a new matrix,
// which reserves what is current then.
//
// The reserve is a list of node blocks (row node, column node), sorted, each with the mask of
// its entries that no element block or fixed entry holds (bit 3i + j); entries are numbered
// block by block from `first_entry` on, bits ascending. The matrix reads it as blocks
// (DirectMatrix: merged into the element blocks' rows, on the device for a device matrix),
// never as a list of entries, which for the 1M stack's 388K contact pairs were 28M (row,
// column) pairs sorted row by row on the host at every new matrix.
#pragma once
#include <petscsys.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "assembly/cuda/group_targets.hpp"
#include "assembly/node_block_reduction.hpp"
#include "device/device_runtime.hpp"

namespace dipc {

class ReservedBlocks {
 public:
  using NodePair = std::array<std::int64_t, 2>;
  // held(row, col): whether an entry outside the node blocks already exists (the fixed part's).
  using Held = std::function<bool(PetscInt row, PetscInt col)>;

  // The reserve of the node pairs (row node, column node) given, in any order and repeated:
  // their blocks' entries that `blocks` and `held` do not hold, numbered from first_entry.
  // Sorts node_pairs in place (unless sorted); the pairs are looked up on the host threads.
  void build(std::vector<NodePair>& node_pairs, const NodeBlockReduction& blocks, const Held& held,
             std::size_t first_entry);
  // The same reserve from its blocks found elsewhere (the device: cuda/group_targets.hpp): the
  // node pairs (rows[p], cols[p]) distinct and ascending, each with the entries that nothing
  // holds yet (masks[p]; pairs with none are left out).
  void assign(const std::vector<std::int64_t>& rows, const std::vector<std::int64_t>& cols,
              const std::vector<std::uint16_t>& masks, const NodeBlockReduction& blocks, std::size_t first_entry);
  void clear();

  std::size_t num_entries() const { return num_entries_; }
  // The blocks, ascending by (row node, column node): block k's nodes, its entries (mask) and
  // their first number.
  std::size_t num_blocks() const { return pairs_.size(); }
  const NodePair& pair(std::size_t k) const { return pairs_[k]; }
  unsigned mask(std::size_t k) const { return mask_[k]; }
  std::size_t start(std::size_t k) const { return start_[k]; }
  // The first block whose row node is not below row_node.
  std::size_t first_of_row(std::int64_t row_node) const;
  // The first entry's number (build's first_entry).
  std::size_t first_entry() const { return first_entry_; }
  // A reserved block: which of its entries the reserve holds (bit 3i + j; none where the
  // reserve has no such block) and the first of them.
  struct Block {
    unsigned mask = 0;
    std::size_t start = 0;
  };
  // The reserve's block of the node pair (row_node, col_node).
  Block find_block(std::int64_t row_node, std::int64_t col_node) const;
  // Appends the global dof ids of every entry, in entry order.
  void entries(std::vector<PetscInt>* rows, std::vector<PetscInt>* cols) const;
  // The blocks to the device, for the changing terms' lookups there (group_targets.hpp), and
  // the reserve fields of *index from them (false, index untouched, where the blocks changed
  // since the last upload). Throws std::length_error where an entry or a block index does not
  // fit 32 bits.
  void upload();
  bool device_index(device::BlockEntryIndex* index) const;
  // The device's column nodes, masks and starts after upload() (null before), which a device
  // matrix's rows read (DirectMatrix).
  const std::int64_t* device_cols() const { return uploaded_ ? d_col_.data() : nullptr; }
  const std::uint16_t* device_masks() const { return uploaded_ ? d_mask_.data() : nullptr; }
  const std::uint32_t* device_starts() const { return uploaded_ ? d_start_.data() : nullptr; }

 private:
  // After the blocks are in place: their entries [first_entry, end_entry) and the dense rows' index.
  void finish(const NodeBlockReduction& blocks, std::size_t first_entry, std::size_t end_entry);

  std::vector<NodePair> pairs_;  // ascending
  // Rows of the blocks' dense range (NodeBlockReduction::dense_begin ..): the pairs of row node
  // dense_begin_ + r are pairs_[dense_first_[r] .. dense_first_[r + 1]), found without a search
  // of the whole reserve (millions of blocks on contact-rich steps); other rows are searched.
  std::int64_t dense_begin_ = 0, dense_end_ = 0;
  std::vector<std::size_t> dense_first_;
  std::vector<std::uint16_t> mask_;  // the block's reserved entries
  std::vector<std::size_t> start_;   // the block's first entry
  std::size_t num_entries_ = 0, first_entry_ = 0;
  bool uploaded_ = false;  // the device arrays hold the blocks
  device::Array<std::int64_t> d_row_{"reserved block rows"}, d_col_{"reserved block columns"};
  device::Array<std::uint16_t> d_mask_{"reserved block masks"};
  device::Array<std::uint32_t> d_start_{"reserved block starts"}, d_dense_first_{"reserved dense row starts"};
};

}  // namespace dipc
