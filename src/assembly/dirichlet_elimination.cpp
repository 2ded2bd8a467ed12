#include "assembly/dirichlet_elimination.hpp"

#include <algorithm>
#include <limits>

namespace dipc {

void DirichletElimination::find(const NodeBlockReduction& blocks, const std::vector<PetscInt>& extra_rows,
                                const std::vector<PetscInt>& extra_cols, const ReservedBlocks& reserve,
                                const std::vector<std::int64_t>& local_to_global, const std::vector<char>& prescribed,
                                PetscInt owned_begin, PetscInt owned_end) {
  // The element blocks' entries are found again only when the blocks or the prescribed dofs
  // change: a pass over every block (27.5M at 1M hexes) at each new matrix of a contact-rich
  // step otherwise, where only the reserve changes.
  const bool same_blocks = blocks.id == blocks_id_ && prescribed == prescribed_ &&
                           local_to_global == local_to_global_ && owned_begin == owned_begin_ &&
                           owned_end == owned_end_;
  if (!same_blocks) {
    blocks_id_ = blocks.id;
    prescribed_ = prescribed, local_to_global_ = local_to_global;
    owned_begin_ = owned_begin, owned_end_ = owned_end;
    // Prescribed global dofs as a bitmap over their id range; a block whose two nodes have none
    // is passed over whole.
    lo_ = std::numeric_limits<PetscInt>::max(), hi_ = -1;
    for (std::size_t n = 0; n < local_to_global.size(); ++n)
      for (int c = 0; c < 3; ++c)
        if (prescribed[3 * n + c]) {
          const PetscInt dof = static_cast<PetscInt>(3 * local_to_global[n] + c);
          lo_ = std::min(lo_, dof), hi_ = std::max(hi_, dof);
        }
    bitmap_.assign(hi_ >= lo_ ? static_cast<std::size_t>(hi_ - lo_ + 1) : 0, false);
    for (std::size_t n = 0; n < local_to_global.size(); ++n)
      for (int c = 0; c < 3; ++c)
        if (prescribed[3 * n + c]) bitmap_[static_cast<PetscInt>(3 * local_to_global[n] + c) - lo_] = true;
  }
  const auto is_prescribed = [&](std::int64_t dof) { return dof >= lo_ && dof <= hi_ && bitmap_[dof - lo_]; };
  const auto node_prescribed = [&](std::int64_t node) {
    return is_prescribed(3 * node) || is_prescribed(3 * node + 1) || is_prescribed(3 * node + 2);
  };
  const auto classify_into = [&](std::vector<std::size_t>& zero, std::vector<std::size_t>& one) {
    return [&](std::size_t u, std::int64_t r, std::int64_t c) {
      if (!is_prescribed(r) && !is_prescribed(c)) return;
      const bool owned_diagonal = r == c && r >= owned_begin && r < owned_end;
      (owned_diagonal ? one : zero).push_back(u);
    };
  };
  if (!same_blocks) {
    block_zero_.clear(), block_one_.clear();
    const auto classify = classify_into(block_zero_, block_one_);
    if (hi_ >= lo_)
      for (std::size_t s = 0; s < blocks.row_nodes.size(); ++s) {
        const std::int64_t row_node = blocks.row_nodes[s];
        const bool row_any = node_prescribed(row_node);
        for (std::size_t k = blocks.row_start[s]; k < blocks.row_start[s + 1]; ++k) {
          if (!row_any && !node_prescribed(blocks.block_col[k])) continue;
          blocks.for_each_entry(row_node, k, classify);
        }
      }
  }
  zero_entries_ = block_zero_, one_entries_ = block_one_;
  if (hi_ < lo_) return;
  const auto classify = classify_into(zero_entries_, one_entries_);
  const std::size_t num_block_entries = blocks.num_entries();
  for (std::size_t v = 0; v < extra_rows.size(); ++v) classify(num_block_entries + v, extra_rows[v], extra_cols[v]);
  for (std::size_t k = 0; k < reserve.num_blocks(); ++k) {
    const auto [row_node, col_node] = reserve.pair(k);
    if (!node_prescribed(row_node) && !node_prescribed(col_node)) continue;
    std::size_t entry = reserve.start(k);
    for (int bit = 0; bit < 9; ++bit)
      if (reserve.mask(k) >> bit & 1u) classify(entry++, 3 * row_node + bit / 3, 3 * col_node + bit % 3);
  }
}

void DirichletElimination::keep_on_device() {
  d_zero_entries_.upload(zero_entries_);
  d_one_entries_.upload(one_entries_);
}

void DirichletElimination::apply(double* unique) const {
  for (std::size_t u : zero_entries_) unique[u] = 0;
  for (std::size_t u : one_entries_) unique[u] = 1;
}

void DirichletElimination::apply_on_device(double* d_unique) const {
  device::eliminate(d_unique, d_zero_entries_.data(), zero_entries_.size(), d_one_entries_.data(), one_entries_.size());
}

}  // namespace dipc
