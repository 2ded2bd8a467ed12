#include "assembly/coo_part.hpp"

#include <limits>
#include <stdexcept>

#include "threads/host_threads.hpp"

namespace dipc {

PetscErrorCode CooPart::build(const PetscInt* rows, const PetscInt* cols, std::size_t n, PetscInt owned_begin,
                              PetscInt owned_end) {
  PetscFunctionBeginUser;
  try {
    reduction_ = CooReduction::build(rows, cols, n, owned_begin, owned_end);
  } catch (const std::length_error& e) {
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_SUP, "%s", e.what());
  }
  PetscFunctionReturn(0);
}

void CooPart::place(const Find& find, std::size_t first_new, std::vector<PetscInt>* extra_rows,
                    std::vector<PetscInt>* extra_cols) {
  // In chunks on the host threads (the lumped mass gives 3 entries per node), each with its own
  // row hint; a chunk's new entries are numbered after the lower chunks', in row order.
  const std::size_t num_scalar = reduction_.num_unique();
  target_.resize(num_scalar);
  constexpr std::size_t kNew = std::numeric_limits<std::size_t>::max();
  std::vector<std::size_t> chunk_new(static_cast<std::size_t>(host_threads()), 0);
  const int chunks = parallel_chunks(num_scalar, [&](int c, std::size_t v0, std::size_t v1) {
    std::size_t row_hint = 0, fresh = 0;  // the unique entries ascend by row
    for (std::size_t v = v0; v < v1; ++v) {
      const std::int64_t k = find(reduction_.rows[v], reduction_.cols[v], &row_hint);
      target_[v] = k >= 0 ? static_cast<std::size_t>(k) : kNew;
      fresh += k < 0;
    }
    chunk_new[static_cast<std::size_t>(c)] = fresh;
  });
  const std::size_t num_new = chunk_starts(chunk_new, chunks)[0];
  if (num_new > 0) {
    const std::size_t before = extra_rows->size();
    extra_rows->resize(before + num_new), extra_cols->resize(before + num_new);
    parallel_chunks(num_scalar, [&](int c, std::size_t v0, std::size_t v1) {
      std::size_t next = chunk_new[static_cast<std::size_t>(c)];
      for (std::size_t v = v0; v < v1; ++v)
        if (target_[v] == kNew) {
          target_[v] = first_new + next;
          (*extra_rows)[before + next] = reduction_.rows[v];
          (*extra_cols)[before + next] = reduction_.cols[v];
          ++next;
        }
    });
  }
  std::vector<PetscInt>().swap(reduction_.rows);
  std::vector<PetscInt>().swap(reduction_.cols);
}

void CooPart::keep_on_device() {
  d_offsets_.upload(reduction_.offsets);
  d_sources_.upload(reduction_.sources);
  std::vector<CooReduction::Index>().swap(reduction_.offsets);
  std::vector<CooReduction::Index>().swap(reduction_.sources);
  d_target_.upload(target_);
}

void CooPart::add(const double* raw, double* unique) {
  const std::size_t num_scalar = target_.size();
  sums_.resize(num_scalar);
  reduction_.reduce(raw, sums_.data());
  for (std::size_t v = 0; v < num_scalar; ++v) unique[target_[v]] += sums_[v];
}

void CooPart::add_on_device(const double* d_raw, double* d_unique) {
  const std::size_t num_scalar = target_.size();
  d_sums_.resize(num_scalar);
  device::reduce_coo(d_raw, d_offsets_.data(), d_sources_.data(), num_scalar, d_sums_.data());
  device::add_at(d_unique, d_target_.data(), d_sums_.data(), num_scalar, std::numeric_limits<std::size_t>::max());
}

}  // namespace dipc
