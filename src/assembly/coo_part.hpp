// CooPart: a part of the Hessian's raw values given as a COO list (the forms without node blocks:
// contact, friction, the lumped mass; small, or changing with the active set) and its reduction
// into the matrix's entries: CooReduction sums the raw values of each distinct (row, col), and
// each distinct entry is added onto the matrix entry that holds it: a node block's or, where none
// does, an "extra" entry after the blocks' (zeroed before the parts add onto them).
#pragma once
#include <petscsys.h>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "assembly/coo_reduction.hpp"
#include "assembly/node_block_reduction.hpp"
#include "device/device_runtime.hpp"

namespace dipc {

class CooPart {
 public:
  // The reduction of the n raw entries (rows[k], cols[k]) on a rank that owns the rows
  // [owned_begin, owned_end) (CooReduction::build).
  PetscErrorCode build(const PetscInt* rows, const PetscInt* cols, std::size_t n, PetscInt owned_begin,
                       PetscInt owned_end);
  // The matrix entry of a dof pair, or -1 where the matrix has none (yet); row_hint as for
  // NodeBlockReduction::find.
  using Find = std::function<std::int64_t(PetscInt row, PetscInt col, std::size_t* row_hint)>;
  // Where each distinct entry goes among the matrix's entries: find(row, col), else a new one
  // from first_new on, whose (row, col) are appended to *extra_rows and *extra_cols (in row
  // order). Frees the reduction's (row, col) lists.
  void place(const Find& find, std::size_t first_new, std::vector<PetscInt>* extra_rows,
             std::vector<PetscInt>* extra_cols);
  // Puts the map on the device for reduce_on_device, and frees the host's copy of the reduction.
  void keep_on_device();

  // Adds the part's sums (raw: its first raw value) onto unique.
  void add(const double* raw, double* unique);
  void add_on_device(const double* d_raw, double* d_unique);

 private:
  CooReduction reduction_;
  std::vector<std::size_t> target_;  // distinct entry -> the matrix's entry
  std::vector<double> sums_;
  device::Array<CooReduction::Index> d_offsets_{"COO reduction offsets"}, d_sources_{"COO reduction sources"};
  device::Array<double> d_sums_{"summed COO values of the other forms"};
  device::Array<std::size_t> d_target_{"COO entries in the matrix"};
};

}  // namespace dipc
