// BlockEntries: where the Hessian matrix keeps the entries of a node block, as the changing
// terms' lookups (TargetPart) ask for them: in the element forms' node blocks
// (NodeBlockReduction), where a block lacks some in the reserve (ReservedBlocks), else among the
// fixed part's extra entries (numbered after the blocks' entries). The three hold disjoint
// entries (ReservedBlocks::build). The device's lookups (cuda/group_targets.hpp) follow the
// same order.
#pragma once
#include <petscsys.h>

#include <cstddef>
#include <cstdint>
#include <vector>

#include "assembly/node_block_reduction.hpp"
#include "assembly/reserved_blocks.hpp"

namespace dipc {

struct BlockEntries {
  const NodeBlockReduction* blocks = nullptr;
  const ReservedBlocks* reserve = nullptr;
  // The fixed part's extra entries, ascending by (row, col): entry blocks->num_entries() + v.
  const std::vector<PetscInt>* extra_rows = nullptr;
  const std::vector<PetscInt>* extra_cols = nullptr;

  // The entry of the dof pair (row, col) among the extra entries, or -1.
  std::int64_t find_extra(PetscInt row, PetscInt col) const;
  // The entries of node block (row_node, col_node)'s 9 dof pairs into entry[3i + j], -1 where
  // the matrix has none; row_hint as for NodeBlockReduction::find_block.
  void find(std::int64_t row_node, std::int64_t col_node, std::size_t* row_hint, std::int64_t entry[9]) const;
};

}  // namespace dipc
