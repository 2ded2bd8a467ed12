// DirichletElimination: the Hessian's rows and columns of prescribed dofs, eliminated
// symmetrically after the values are summed: zero in a prescribed row or column, one on an owned
// prescribed diagonal (a ghost row's diagonal is its owner's). Newton then never moves those
// dofs and CG sees an SPD matrix. The owned prescribed diagonals are in the matrix's pattern
// whatever the forms give (HessianAssembler adds them), so kinematic nodes, of which no element
// is assembled, get one.
#pragma once
#include <petscsys.h>

#include <cstddef>
#include <cstdint>
#include <vector>

#include "assembly/node_block_reduction.hpp"
#include "assembly/reserved_blocks.hpp"
#include "device/device_runtime.hpp"

namespace dipc {

class DirichletElimination {
 public:
  // The entries to set among the matrix's: those of `blocks`, then the extra ones (extra_rows[v],
  // extra_cols[v]) from blocks.num_entries() on, then the reserve's (numbered as it says).
  // prescribed: 3 flags per local node, whose global ids are local_to_global; the rank owns the
  // dofs [owned_begin, owned_end).
  void find(const NodeBlockReduction& blocks, const std::vector<PetscInt>& extra_rows,
            const std::vector<PetscInt>& extra_cols, const ReservedBlocks& reserve,
            const std::vector<std::int64_t>& local_to_global, const std::vector<char>& prescribed, PetscInt owned_begin,
            PetscInt owned_end);
  void keep_on_device();

  void apply(double* unique) const;
  void apply_on_device(double* d_unique) const;

 private:
  std::vector<std::size_t> zero_entries_, one_entries_;
  // The element blocks' share of them and what it was found for (the blocks, the prescribed
  // flags, their nodes' global ids, the owned dofs), and the prescribed dofs' bitmap over
  // [lo_, hi_].
  std::vector<std::size_t> block_zero_, block_one_;
  std::uint64_t blocks_id_ = 0;
  std::vector<char> prescribed_;
  std::vector<std::int64_t> local_to_global_;
  PetscInt owned_begin_ = 0, owned_end_ = 0, lo_ = 0, hi_ = -1;
  std::vector<bool> bitmap_;
  device::Array<std::size_t> d_zero_entries_{"Dirichlet zero entries"}, d_one_entries_{"Dirichlet diagonal entries"};
};

}  // namespace dipc
