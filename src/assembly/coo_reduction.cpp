#include "assembly/coo_reduction.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <string>

namespace dipc {

namespace {
constexpr CooReduction::Index kDropped = std::numeric_limits<CooReduction::Index>::max();

struct Entry {
  PetscInt col;
  CooReduction::Index source;
};
}  // namespace

CooReduction CooReduction::build(const PetscInt* rows, const PetscInt* cols, std::size_t n, PetscInt dense_begin,
                                 PetscInt dense_end) {
  // Raw ids must fit Index with one value to spare (the limit documented in the header).
  if (n >= kDropped)
    throw std::length_error("COO pattern of " + std::to_string(n) +
                            " entries on one rank exceeds 2^32 - 1; run on more ranks");
  dense_end = std::max(dense_begin, dense_end);
  const auto kept = [&](std::size_t k) { return rows[k] >= 0 && cols[k] >= 0; };
  const auto in_dense = [&](PetscInt r) { return r >= dense_begin && r < dense_end; };

  // A counting sort by row needs rows numbered densely. A histogram over [min row, max row]
  // would span the whole global matrix on a rank whose ghost rows lie at both ends, memory that
  // grows with the global size on every rank; instead the dense range (the owned rows, which
  // are contiguous) is indexed directly and the few other rows (ghosts) are numbered by their
  // rank among the distinct ones, found by sorting those entries' rows alone.
  std::vector<PetscInt> sparse;
  for (std::size_t k = 0; k < n; ++k)
    if (kept(k) && !in_dense(rows[k])) sparse.push_back(rows[k]);
  std::sort(sparse.begin(), sparse.end());
  sparse.erase(std::unique(sparse.begin(), sparse.end()), sparse.end());
  sparse.shrink_to_fit();
  const std::size_t dense_size = static_cast<std::size_t>(dense_end - dense_begin);
  const std::size_t below = static_cast<std::size_t>(std::lower_bound(sparse.begin(), sparse.end(), dense_begin) -
                                                     sparse.begin());
  const std::size_t num_rows = dense_size + sparse.size();
  if (num_rows >= kDropped) throw std::length_error("COO pattern spans more than 2^32 - 1 rows on one rank");
  // Row numbers in increasing row order: sparse rows below the range, the range, sparse above.
  const auto row_of = [&](std::size_t s) -> PetscInt {
    if (s < below) return sparse[s];
    if (s < below + dense_size) return dense_begin + static_cast<PetscInt>(s - below);
    return sparse[s - dense_size];
  };

  // Counting sort by row: entries go to their row's bucket in raw order, so the sources of a
  // row's bucket are ascending. The bucket of an entry is computed in both passes rather than
  // stored: a stored slot per raw entry (4 bytes, hundreds per element) raised the setup's peak.
  const auto slot_of = [&](std::size_t k) -> std::size_t {
    const PetscInt r = rows[k];
    if (in_dense(r)) return below + static_cast<std::size_t>(r - dense_begin);
    return static_cast<std::size_t>(std::lower_bound(sparse.begin(), sparse.end(), r) - sparse.begin()) +
           (r >= dense_end ? dense_size : 0);
  };
  std::vector<Index> start(num_rows + 1, 0);
  for (std::size_t k = 0; k < n; ++k)
    if (kept(k)) ++start[slot_of(k) + 1];
  for (std::size_t s = 0; s < num_rows; ++s) start[s + 1] += start[s];
  const std::size_t num_kept = start[num_rows];
  std::vector<Entry> bucket(num_kept);
  {
    std::vector<Index> next(start.begin(), start.end() - 1);
    for (std::size_t k = 0; k < n; ++k)
      if (kept(k)) bucket[next[slot_of(k)]++] = {cols[k], static_cast<Index>(k)};
  }

  // Each row's few hundred entries by column, ties by raw id (the fixed summation order).
  std::size_t num_unique = 0;
  for (std::size_t s = 0; s < num_rows; ++s) {
    Entry* b = bucket.data() + start[s];
    Entry* e = bucket.data() + start[s + 1];
    std::sort(b, e,
              [](const Entry& x, const Entry& y) { return x.col < y.col || (x.col == y.col && x.source < y.source); });
    for (const Entry* it = b; it != e; ++it)
      if (it == b || it->col != (it - 1)->col) ++num_unique;
  }

  CooReduction r;
  r.num_raw = n;
  r.rows.reserve(num_unique);
  r.cols.reserve(num_unique);
  r.offsets.reserve(num_unique + 1);
  r.sources.resize(num_kept);
  for (std::size_t s = 0; s < num_rows; ++s) {
    const PetscInt row = row_of(s);
    for (std::size_t j = start[s]; j < start[s + 1]; ++j) {
      if (j == start[s] || bucket[j].col != bucket[j - 1].col) {
        r.rows.push_back(row);
        r.cols.push_back(bucket[j].col);
        r.offsets.push_back(static_cast<Index>(j));
      }
      r.sources[j] = bucket[j].source;
    }
  }
  r.offsets.push_back(static_cast<Index>(num_kept));
  return r;
}

void CooReduction::reduce(const double* raw, double* unique) const {
  const std::size_t m = num_unique();
  for (std::size_t u = 0; u < m; ++u) {
    double sum = 0;
    for (Index j = offsets[u]; j < offsets[u + 1]; ++j) sum += raw[sources[j]];
    unique[u] = sum;
  }
}

}  // namespace dipc
