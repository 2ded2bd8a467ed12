// CooReduction: the distinct (row, col) entries of a raw COO list, and the map that sums the
// raw values of each.
//
// The forms' concatenated Hessian patterns repeat most matrix entries (a hex mesh's interior
// entry appears in ~2.4 of the 576-entry element blocks), and MatSetPreallocationCOO spent most
// of the matrix setup comparison-sorting that raw list. PETSc gets the unique list instead,
// sorted by row then column, and the raw values (which forms and the Dirichlet elimination keep
// writing in raw order) are summed into it by reduce() on the host or device::reduce_coo on the
// device, with the same CSR map, in the same order, so both give the same bits.
#pragma once
#include <petscsys.h>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace dipc {

struct CooReduction {
  // 32-bit indices into the raw list halve the map's memory (it is mirrored on the device); a
  // rank is then limited to 2^32 - 1 raw entries, about 7 million hex elements, which build()
  // checks.
  using Index = std::uint32_t;

  // Builds the reduction of the n raw entries (rows[k], cols[k]). Entries with a negative row or
  // column are dropped, as MatSetPreallocationCOO ignores them. Rows in [dense_begin, dense_end)
  // are bucketed by a direct index, so that range should be the rows holding most entries (this
  // rank's owned rows); any other row works, at the cost of a sort over the entries outside it.
  // Throws std::length_error when n does not fit Index.
  static CooReduction build(const PetscInt* rows, const PetscInt* cols, std::size_t n, PetscInt dense_begin,
                            PetscInt dense_end);

  std::size_t num_unique() const { return offsets.empty() ? 0 : offsets.size() - 1; }
  // unique[u] = Σ raw[sources[j]], j in [offsets[u], offsets[u+1]), summed from 0 in that order.
  void reduce(const double* raw, double* unique) const;

  // The unique entries, by row then column; reduce() does not read them, so a caller may move
  // them out (to MatSetPreallocationCOO, which may reorder them).
  std::vector<PetscInt> rows, cols;
  std::vector<Index> offsets;  // num_unique() + 1 starts into sources
  std::vector<Index> sources;  // raw ids of each unique entry, ascending; dropped ones absent
  std::size_t num_raw = 0;
};

}  // namespace dipc
