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
// block by block from `first_entry` on, bits ascending.
#pragma once
#include <petscsys.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "assembly/node_block_reduction.hpp"

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
  void clear() { *this = ReservedBlocks(); }

  std::size_t num_entries() const { return num_entries_; }
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

 private:
  std::vector<NodePair> pairs_;      // ascending
  // Rows of the blocks' dense range (NodeBlockReduction::dense_begin ..): the pairs of row node
  // dense_begin_ + r are pairs_[dense_first_[r] .. dense_first_[r + 1]), found without a search
  // of the whole reserve (millions of blocks on contact-rich steps); other rows are searched.
  std::int64_t dense_begin_ = 0, dense_end_ = 0;
  std::vector<std::size_t> dense_first_;
  std::vector<std::uint16_t> mask_;  // the block's reserved entries
  std::vector<std::size_t> start_;   // the block's first entry
  std::size_t num_entries_ = 0;
};

}  // namespace dipc
