#include "assembly/direct_matrix.hpp"

#include <algorithm>
#include <memory>
#include <stdexcept>
#include <type_traits>
#include <utility>

#include "assembly/cuda/block_rows.hpp"
#include "logging/log_stages.hpp"
#include "partition/mpi_exchange.hpp"
#include "threads/host_threads.hpp"

// PetscObjectStateIncrease: PETSc's objects count their changes in a state that the solvers
// compare (a preconditioner is set up again when its matrix's state moved); values written
// into the arrays directly must move it too. PETSc declares it with its object internals.
#include <petsc/private/petscimpl.h>

#if PetscDefined(HAVE_HYPRE_DEVICE)
#include <_hypre_parcsr_mv.h>
#include <petsc/private/petschypre.h>  // PetscHYPREInitialize: hypre's device state, as PETSc starts it
#include <petscmathypre.h>
#endif

namespace dipc {

namespace {
// A provisional position in the off-diagonal block, made final once the diagonal block's size
// is known (positions stay below 2^31: a rank's nonzeros fit PetscInt, checked by the caller).
constexpr std::uint32_t kOffdFlag = 0x80000000u;

struct Pair {
  PetscInt row, col;
};
using Entry = std::pair<PetscInt, std::uint32_t>;  // (column, source)

// Rows a chunk of the host threads holds at the least, in both passes over the rows.
constexpr std::size_t kRowGrain = 512;

// The arrays a host AIJ matrix uses without copying them; owned by the Mat (composed on it), so
// that an older matrix keeps its own while a newer one is in use.
struct HostArrays {
  std::vector<PetscInt> diag_i, offd_i, offd_j;
  LargePageVector<PetscInt> diag_j;
  LargePageVector<double> diag_a;
  std::vector<double> offd_a;
};

PetscErrorCode destroy_host_arrays(void* ctx) {
  delete static_cast<HostArrays*>(ctx);
  return 0;
}
}  // namespace

DirectMatrix::Kind DirectMatrix::kind_of(Mat J) {
  PetscBool aij = PETSC_FALSE, hypre = PETSC_FALSE;
  const auto object = reinterpret_cast<PetscObject>(J);
  PetscCallAbort(PetscObjectComm(object), PetscObjectTypeCompareAny(object, &aij, MATSEQAIJ, MATMPIAIJ, ""));
  PetscCallAbort(PetscObjectComm(object), PetscObjectTypeCompare(object, MATHYPRE, &hypre));
  if (aij) return Kind::host_aij;
  if (hypre && PetscDefined(HAVE_HYPRE_DEVICE) && device::built_with_cuda()) return Kind::device_hypre;
  return Kind::coo;
}

PetscErrorCode DirectMatrix::create(Mat like, Kind kind, const NodeBlockReduction* blocks,
                                    const ReservedBlocks* reserve, const PetscInt* rows, const PetscInt* cols,
                                    std::size_t n, Mat* J) {
  PetscFunctionBeginUser;
  PetscCheck(kind != Kind::coo, PETSC_COMM_SELF, PETSC_ERR_PLIB, "DirectMatrix::create needs a direct kind");
  MPI_Comm comm = PetscObjectComm(reinterpret_cast<PetscObject>(like));
  kind_ = kind;
  num_entries_ = (blocks ? blocks->num_entries() : 0) + n;
  if (reserve && reserve->num_blocks() == 0) reserve = nullptr;
  if (reserve) {
    PetscCheck(blocks && reserve->first_entry() == num_entries_, PETSC_COMM_SELF, PETSC_ERR_PLIB,
               "the reserve's entries must follow the node blocks' and the list's");
    PetscCheck(kind != Kind::device_hypre || reserve->device_cols(), PETSC_COMM_SELF, PETSC_ERR_PLIB,
               "a device matrix's reserve must be on the device");
    num_entries_ += reserve->num_entries();
  }
  // Every rank's first row, from the local sizes: the template's layout is not set up yet (its
  // global size may still read PETSC_DETERMINE).
  int rank, size;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscInt m;
  PetscCall(MatGetLocalSize(like, &m, nullptr));
  row_starts_.assign(size + 1, 0);
  PetscCallMPI(MPI_Allgather(&m, 1, MPIU_INT, row_starts_.data() + 1, 1, MPIU_INT, comm));
  for (int r = 0; r < size; ++r) row_starts_[r + 1] += row_starts_[r];
  row_begin_ = row_starts_[rank];
  {
    EventScope event(log_events().matrix_rows);
    PetscCall(build_pattern(comm, m, blocks, reserve, rows, cols, n));
  }
  EventScope event(log_events().matrix_make);
  if (kind == Kind::host_aij)
    PetscCall(make_host_aij(like, J));
  else
    PetscCall(make_device_hypre(like, blocks, reserve, J));
  if (kind == Kind::device_hypre) {
    d_slot_position_.upload(slot_position_);
    d_slot_keep_.upload(slot_keep_);
  }
  PetscFunctionReturn(0);
}

// The entries of the rank's rows [row_begin, row_begin + num_rows) while build_pattern runs.
// Entries are numbered: the blocks' first (nb of them), then the list's (nb + k), then the
// reserve's (its own numbers, from nb + n); entries received from other ranks are numbered on
// after them (total + k) while the rows are built.
// The matrix is square: a row's diagonal block holds the columns of the rank's own rows.
struct DirectMatrix::RowEntries {
  const NodeBlockReduction* blocks;
  const ReservedBlocks* reserve;
  const PetscInt* rows;
  const PetscInt* cols;
  std::size_t n, nb, total;
  PetscInt num_rows, row_begin;
  // hypre's matrix on the device: its rows hold the diagonal first (as hypre's smoothers read
  // it), and those made of node blocks alone are written there (make_device_hypre).
  bool on_device;
  std::vector<std::int64_t> block_row_of_node;      // per own node, its row of the node blocks (-1: none)
  const std::vector<std::uint32_t>* reserve_first;  // per own node, its reserve blocks' range
  std::vector<Pair> received;                       // entries of own rows sent by other ranks
  std::vector<int> from;                            // the ranks that sent them
  // The list's own entries and the received ones by row: row r's are source[row_count[r] ..
  // row_count[r + 1]).
  std::vector<std::size_t> row_count;
  std::vector<std::uint32_t> source;

  bool own_row(PetscInt row) const { return row >= row_begin && row < row_begin + num_rows; }
  bool is_diag(PetscInt col) const { return own_row(col); }
  bool is_received(std::uint32_t src) const { return src >= total; }
  PetscInt column_of(std::uint32_t src) const { return is_received(src) ? received[src - total].col : cols[src - nb]; }
  std::int64_t block_row(PetscInt r) const { return blocks ? block_row_of_node[static_cast<std::size_t>(r / 3)] : -1; }
  // Row r's reserve blocks [*first, *last).
  void reserve_range(PetscInt r, std::size_t* first, std::size_t* last) const {
    *first = *last = 0;
    if (!reserve) return;
    *first = (*reserve_first)[static_cast<std::size_t>(r / 3)],
    *last = (*reserve_first)[static_cast<std::size_t>(r / 3) + 1];
  }
  // Rows made of node blocks alone (most rows), the element forms' and the reserve's: distinct
  // and ascending, read in place.
  bool blocks_only(PetscInt r) const { return block_row(r) >= 0 && row_count[r] == row_count[r + 1]; }
  // f(column, entry) for the block entries of row r (element blocks and reserve), columns
  // ascending: the two block lists merged by column node (a node pair may be in both, the
  // reserve holding the entries the element block lacks).
  template <class F>
  void walk_blocks(PetscInt r, F&& f) const {
    const std::int64_t s = block_row(r);
    const int i = static_cast<int>(r % 3);
    std::size_t k = s >= 0 ? blocks->row_start[s] : 0, k_end = s >= 0 ? blocks->row_start[s + 1] : 0, e, e_end;
    reserve_range(r, &e, &e_end);
    while (k < k_end || e < e_end) {
      const std::int64_t col = k < k_end && (e == e_end || blocks->block_col[k] <= reserve->pair(e)[1])
                                   ? blocks->block_col[k]
                                   : reserve->pair(e)[1];
      const unsigned held = k < k_end && blocks->block_col[k] == col ? blocks->block_mask[k] : 0u;
      const unsigned reserved = e < e_end && reserve->pair(e)[1] == col ? reserve->mask(e) : 0u;
      for (int j = 0; j < 3; ++j) {
        const int bit = 3 * i + j;
        if (held >> bit & 1u)
          f(static_cast<PetscInt>(3 * col + j),
            static_cast<std::uint32_t>(blocks->block_start[k] + entry_in_block(held, bit)));
        else if (reserved >> bit & 1u)
          f(static_cast<PetscInt>(3 * col + j),
            static_cast<std::uint32_t>(reserve->start(e) + entry_in_block(reserved, bit)));
      }
      if (k < k_end && blocks->block_col[k] == col) ++k;
      if (e < e_end && reserve->pair(e)[1] == col) ++e;
    }
  }

  // The list's own entries and the received ones, bucketed by row (counting sort, in 4 B): the
  // list's entry k as nb + k, received entry k as total + k, so that own entries sort first,
  // then the received ones in arrival order.
  // On the host threads, each taking a range of rows and scanning the whole list for them (a
  // per-thread count of every row would cost more memory than the list).
  void bucket_by_row() {
    const std::size_t ranges = static_cast<std::size_t>(host_threads());
    const auto for_rows_of_ranges = [&](auto&& f) {
      parallel_for(
          ranges,
          [&](std::size_t q0, std::size_t q1) {
            const PetscInt first = static_cast<PetscInt>(split_point(row_begin, row_begin + num_rows, q0, ranges));
            const PetscInt last = static_cast<PetscInt>(split_point(row_begin, row_begin + num_rows, q1, ranges));
            for (std::size_t k = 0; k < n; ++k)
              if (rows[k] >= first && rows[k] < last) f(k, rows[k] - row_begin);
          },
          1);
    };
    row_count.assign(static_cast<std::size_t>(num_rows) + 1, 0);
    for_rows_of_ranges([&](std::size_t, PetscInt r) { ++row_count[r + 1]; });
    for (const Pair& p : received) ++row_count[p.row - row_begin + 1];
    for (PetscInt r = 0; r < num_rows; ++r) row_count[r + 1] += row_count[r];
    source.resize(row_count[num_rows]);
    std::vector<std::size_t> next(row_count.begin(), row_count.end() - 1);
    for_rows_of_ranges([&](std::size_t k, PetscInt r) { source[next[r]++] = static_cast<std::uint32_t>(nb + k); });
    for (std::size_t k = 0; k < received.size(); ++k)
      source[next[received[k].row - row_begin]++] = static_cast<std::uint32_t>(total + k);
  }

  // The entries of a row that is not node blocks alone, by column: own entries first, then
  // received ones in arrival order.
  void sorted_line(PetscInt r, std::vector<Entry>& line) const {
    line.clear();
    walk_blocks(r, [&](PetscInt col, std::uint32_t entry) { line.emplace_back(col, entry); });
    for (std::size_t k = row_count[r]; k < row_count[r + 1]; ++k) line.emplace_back(column_of(source[k]), source[k]);
    // The element blocks give most rows already sorted.
    if (!std::is_sorted(line.begin(), line.end())) std::sort(line.begin(), line.end());
    const PetscInt row = row_begin + r;
    if (on_device) std::stable_partition(line.begin(), line.end(), [&](const Entry& e) { return e.first == row; });
  }
};

// What a chunk's rows add to the lists kept in row order: counted, then their starts.
struct DirectMatrix::ChunkCounts {
  std::size_t slots = 0, side_diag = 0, side_offd = 0, side_position = 0;
};

PetscErrorCode DirectMatrix::build_pattern(MPI_Comm comm, PetscInt num_rows, const NodeBlockReduction* blocks,
                                           const ReservedBlocks* reserve, const PetscInt* rows, const PetscInt* cols,
                                           std::size_t n) {
  PetscFunctionBeginUser;
  RowEntries entries;
  entries.blocks = blocks;
  entries.reserve = reserve;
  entries.rows = rows;
  entries.cols = cols;
  entries.n = n;
  entries.nb = blocks ? blocks->num_entries() : 0;
  entries.total = num_entries_;
  entries.num_rows = num_rows;
  entries.row_begin = row_begin_;
  entries.on_device = kind_ == Kind::device_hypre;
  PetscCheck(!blocks || (row_begin_ % 3 == 0 && num_rows % 3 == 0), PETSC_COMM_SELF, PETSC_ERR_ARG_SIZ,
             "node blocks need the rank's rows to start and end at a node (rows %" PetscInt_FMT " .. %" PetscInt_FMT
             ")",
             row_begin_, row_begin_ + num_rows);
  // Each own node's reserve blocks, found once (its blocks ascend by row node).
  reserve_first_.clear();
  if (reserve) {
    PetscCheck(reserve->num_blocks() < 0xffffffffu, PETSC_COMM_SELF, PETSC_ERR_SUP,
               "%zu reserved blocks on one rank, more than 32-bit indices hold: run on more ranks",
               reserve->num_blocks());
    const std::int64_t first_node = row_begin_ / 3;
    reserve_first_.resize(static_cast<std::size_t>(num_rows / 3) + 1);
    for (std::size_t q = 0; q < reserve_first_.size(); ++q)
      reserve_first_[q] = static_cast<std::uint32_t>(reserve->first_of_row(first_node + static_cast<std::int64_t>(q)));
  }
  entries.reserve_first = &reserve_first_;
  std::vector<std::vector<std::uint32_t>> remote_entry;
  PetscCall(send_remote_entries(comm, entries, &remote_entry));
  entries.bucket_by_row();

  // Per row: its distinct columns in the kind's order, each given the next position of its
  // block; an own entry takes that position, received ones a slot there. The rows go in chunks
  // on the host threads, in two passes: the first counts each row's columns, the second writes
  // every row at the place the counts give. The arrays are those of one pass in row order, for
  // any number of threads. A row that is not node blocks alone is sorted in both passes: keeping
  // its entries between them cost 150 MB per rank at 4M hexes on 4 ranks, where the rows on the
  // partition's boundary receive millions of entries.
  std::vector<ChunkCounts> chunk = count_row_columns(entries);
  std::vector<std::uint32_t> received_slot = write_rows(entries, chunk);
  std::vector<std::uint32_t>().swap(entries.source);
  finish_offd_positions();

  // The values of other ranks' rows travel to their owners at every assembly, in the order sent.
  remote_.setup(comm, remote_entry, entries.from, std::move(received_slot), slot_position_.size(), entries.on_device);
  PetscFunctionReturn(0);
}

// Entries of other ranks' rows go to their owners, which give each a slot; their values
// follow at every assembly in the order sent. An own node's block row is read in place later;
// a ghost node's (the few on the partition's boundary) is expanded to its entries here.
PetscErrorCode DirectMatrix::send_remote_entries(MPI_Comm comm, RowEntries& entries,
                                                 std::vector<std::vector<std::uint32_t>>* remote_entry) {
  PetscFunctionBeginUser;
  const NodeBlockReduction* blocks = entries.blocks;
  const std::vector<PetscInt>& starts = row_starts_;
  const int size = static_cast<int>(starts.size()) - 1;
  const auto owner_of = [&](PetscInt row) {
    return static_cast<int>(std::upper_bound(starts.begin(), starts.end(), row) - starts.begin()) - 1;
  };
  if (entries.on_device)
    LargePageVector<std::uint32_t>().swap(position_);
  else
    position_.assign(entries.total, kRemote);
  std::vector<std::vector<Pair>> to(size);
  remote_entry->assign(size, {});
  const PetscInt first_node = entries.row_begin / 3;
  entries.block_row_of_node.assign(blocks ? static_cast<std::size_t>(entries.num_rows / 3) : 0, -1);
  if (blocks) {
    for (std::size_t s = 0; s < blocks->row_nodes.size(); ++s) {
      const std::int64_t node = blocks->row_nodes[s];
      if (entries.own_row(static_cast<PetscInt>(3 * node))) {
        entries.block_row_of_node[static_cast<std::size_t>(node - first_node)] = static_cast<std::int64_t>(s);
        continue;
      }
      const int owner = owner_of(static_cast<PetscInt>(3 * node));
      for (std::size_t k = blocks->row_start[s]; k < blocks->row_start[s + 1]; ++k)
        blocks->for_each_entry(node, k, [&](std::size_t entry, std::int64_t row, std::int64_t col) {
          to[owner].push_back({static_cast<PetscInt>(row), static_cast<PetscInt>(col)});
          (*remote_entry)[owner].push_back(static_cast<std::uint32_t>(entry));
        });
    }
  }
  // The reserve's blocks of other ranks' rows lie before and after the own nodes'.
  if (const ReservedBlocks* reserve = entries.reserve) {
    const auto send_blocks = [&](std::size_t k0, std::size_t k1) {
      for (std::size_t k = k0; k < k1; ++k) {
        const auto [row_node, col_node] = reserve->pair(k);
        const int owner = owner_of(static_cast<PetscInt>(3 * row_node));
        std::size_t entry = reserve->start(k);
        for (int bit = 0; bit < 9; ++bit)
          if (reserve->mask(k) >> bit & 1u) {
            to[owner].push_back(
                {static_cast<PetscInt>(3 * row_node + bit / 3), static_cast<PetscInt>(3 * col_node + bit % 3)});
            (*remote_entry)[owner].push_back(static_cast<std::uint32_t>(entry++));
          }
      }
    };
    send_blocks(0, reserve_first_.front());
    send_blocks(reserve_first_.back(), reserve->num_blocks());
  }
  for (std::size_t k = 0; k < entries.n; ++k)
    if (!entries.own_row(entries.rows[k])) {
      const int owner = owner_of(entries.rows[k]);
      to[owner].push_back({entries.rows[k], entries.cols[k]});
      (*remote_entry)[owner].push_back(static_cast<std::uint32_t>(entries.nb + k));
    }
  entries.received = exchange_records(std::move(to), comm, &entries.from);
  PetscCheck(entries.total + entries.received.size() < kRemote, PETSC_COMM_SELF, PETSC_ERR_SUP,
             "%zu matrix entries on one rank, more than the matrix's 32-bit positions hold: run on more ranks",
             entries.total + entries.received.size());
  PetscFunctionReturn(0);
}

// The first pass: each row's column counts (diag_i_, offd_i_ made row starts), the rows the
// device writes, and each chunk's start in the lists kept in row order; sizes those lists.
std::vector<DirectMatrix::ChunkCounts> DirectMatrix::count_row_columns(const RowEntries& entries) {
  const NodeBlockReduction* blocks = entries.blocks;
  const PetscInt num_rows = entries.num_rows;
  const bool on_device = entries.on_device;
  const PetscInt node_begin = entries.row_begin / 3, node_end = (entries.row_begin + num_rows) / 3;
  std::vector<ChunkCounts> chunk(static_cast<std::size_t>(host_threads()));
  diag_i_.assign(static_cast<std::size_t>(num_rows) + 1, 0);
  offd_i_.assign(static_cast<std::size_t>(num_rows) + 1, 0);
  device_block_row_.assign(on_device ? static_cast<std::size_t>(num_rows) : 0, -1);
  const int chunks = parallel_chunks(
      static_cast<std::size_t>(num_rows),
      [&](int c, std::size_t r0, std::size_t r1) {
        ChunkCounts& mine = chunk[static_cast<std::size_t>(c)];
        std::vector<Entry> line;
        for (PetscInt r = static_cast<PetscInt>(r0); r < static_cast<PetscInt>(r1); ++r) {
          const std::int64_t s = entries.block_row(r);
          const int i = static_cast<int>(r % 3);
          PetscInt n_diag = 0, n_offd = 0;
          if (entries.blocks_only(r)) {
            // The row's entries of a block (mask, column node): its bits of row i.
            const auto count = [&](unsigned mask, std::int64_t col_node) {
              (col_node >= node_begin && col_node < node_end ? n_diag : n_offd) += kBlockMaskBits[mask >> (3 * i) & 7u];
            };
            for (std::size_t k = blocks->row_start[s]; k < blocks->row_start[s + 1]; ++k)
              count(blocks->block_mask[k], blocks->block_col[k]);
            std::size_t e, e_end;
            entries.reserve_range(r, &e, &e_end);
            for (; e < e_end; ++e) count(entries.reserve->mask(e), entries.reserve->pair(e)[1]);
            if (on_device) device_block_row_[static_cast<std::size_t>(r)] = s;  // written there (write_block_rows)
          } else {
            entries.sorted_line(r, line);
            for (std::size_t a = 0; a < line.size();) {
              std::size_t b = a + 1;
              while (b < line.size() && line[b].first == line[a].first) ++b;
              const bool own = !entries.is_received(line[a].second);
              (entries.is_diag(line[a].first) ? n_diag : n_offd) += 1;
              if (on_device)
                (entries.is_diag(line[a].first) ? mine.side_diag : mine.side_offd) += 1, mine.side_position += own;
              mine.slots += b > a + (own ? 1 : 0);
              a = b;
            }
          }
          diag_i_[r + 1] = n_diag;
          offd_i_[r + 1] = n_offd;
        }
      },
      kRowGrain);
  for (PetscInt r = 0; r < num_rows; ++r) diag_i_[r + 1] += diag_i_[r], offd_i_[r + 1] += offd_i_[r];
  num_diag_ = static_cast<std::uint32_t>(diag_i_[num_rows]);
  num_offd_ = static_cast<std::uint32_t>(offd_i_[num_rows]);
  std::size_t total_slots = 0, total_side_diag = 0, total_side_offd = 0, total_side_position = 0;
  for (int c = 0; c < chunks; ++c) {
    ChunkCounts& k = chunk[static_cast<std::size_t>(c)];
    total_slots += std::exchange(k.slots, total_slots);
    total_side_diag += std::exchange(k.side_diag, total_side_diag);
    total_side_offd += std::exchange(k.side_offd, total_side_offd);
    total_side_position += std::exchange(k.side_position, total_side_position);
  }
  if (on_device) {
    diag_j_.clear(), offd_j_.clear();
  } else {
    diag_j_.resize(num_diag_);
    offd_j_.resize(num_offd_);
  }
  side_diag_.resize(total_side_diag), side_offd_.resize(total_side_offd), side_position_.resize(total_side_position);
  slot_position_.resize(total_slots);
  slot_keep_.resize(total_slots);
  return chunk;
}

// The second pass: every row's columns and positions at the place the first pass gave it (the
// off-diagonal block's provisional), and the slots of the received entries, which it returns.
std::vector<std::uint32_t> DirectMatrix::write_rows(const RowEntries& entries, std::vector<ChunkCounts>& chunk) {
  const bool on_device = entries.on_device;
  const PetscInt col_begin = entries.row_begin;
  std::vector<std::uint32_t> received_slot(entries.received.size());
  parallel_chunks(
      static_cast<std::size_t>(entries.num_rows),
      [&](int c, std::size_t r0, std::size_t r1) {
        ChunkCounts& mine = chunk[static_cast<std::size_t>(c)];
        std::vector<Entry> line_entries;
        for (PetscInt r = static_cast<PetscInt>(r0); r < static_cast<PetscInt>(r1); ++r) {
          // A column's place in its block (a provisional one in the off-diagonal block).
          std::uint32_t d = static_cast<std::uint32_t>(diag_i_[r]), o = static_cast<std::uint32_t>(offd_i_[r]);
          const auto next_position = [&](PetscInt col) {
            if (entries.is_diag(col)) {
              if (on_device)
                side_diag_[mine.side_diag++] = {d, col - col_begin};
              else
                diag_j_[d] = col - col_begin;
              return d++;
            }
            if (on_device)
              side_offd_[mine.side_offd++] = {o, col};
            else
              offd_j_[o] = col;
            return kOffdFlag | o++;
          };
          if (entries.blocks_only(r)) {
            if (on_device) continue;
            entries.walk_blocks(r, [&](PetscInt col, std::uint32_t entry) { position_[entry] = next_position(col); });
            continue;
          }
          entries.sorted_line(r, line_entries);
          const Entry* line = line_entries.data();
          const std::size_t size = line_entries.size();
          for (std::size_t a = 0; a < size;) {
            std::size_t b = a + 1;
            while (b < size && line[b].first == line[a].first) ++b;
            const std::uint32_t p = next_position(line[a].first);
            const bool own = !entries.is_received(line[a].second);
            if (own) {
              if (on_device)
                side_position_[mine.side_position++] = {line[a].second, p};
              else
                position_[line[a].second] = p;
            }
            if (b > a + (own ? 1 : 0)) {
              const std::size_t slot = mine.slots++;
              for (std::size_t c2 = a + (own ? 1 : 0); c2 < b; ++c2)
                received_slot[line[c2].second - entries.total] = static_cast<std::uint32_t>(slot);
              slot_position_[slot] = p;
              slot_keep_[slot] = own ? 1 : 0;
            }
            a = b;
          }
        }
      },
      kRowGrain);
  return received_slot;
}

// The off-diagonal block's provisional positions made final, now that the diagonal block's
// size is known.
void DirectMatrix::finish_offd_positions() {
  const auto finish = [&](std::uint32_t& p) {
    if (p != kRemote && (p & kOffdFlag)) p = num_diag_ + (p & ~kOffdFlag);
  };
  if (num_offd_ > 0) {
    parallel_for(position_.size(), [&](std::size_t k0, std::size_t k1) {
      for (std::size_t k = k0; k < k1; ++k) finish(position_[k]);
    });
    for (auto& [entry, p] : side_position_) finish(p);
    for (std::uint32_t& p : slot_position_) finish(p);
  }
}

PetscErrorCode DirectMatrix::make_host_aij(Mat like, Mat* J) {
  PetscFunctionBeginUser;
  MPI_Comm comm = PetscObjectComm(reinterpret_cast<PetscObject>(like));
  PetscInt m, bs;
  PetscCall(MatGetLocalSize(like, &m, nullptr));
  PetscCall(MatGetBlockSize(like, &bs));
  PetscBool seq;
  PetscCall(PetscObjectTypeCompare(reinterpret_cast<PetscObject>(like), MATSEQAIJ, &seq));
  const std::vector<PetscInt> offd_columns(offd_j_);
  auto arrays = std::make_unique<HostArrays>();
  arrays->diag_i = std::move(diag_i_);
  arrays->diag_j = std::move(diag_j_);
  arrays->diag_a.assign(num_diag_, 0.0);
  if (seq) {
    PetscCall(
        MatCreateSeqAIJWithArrays(comm, m, m, arrays->diag_i.data(), arrays->diag_j.data(), arrays->diag_a.data(), J));
  } else {
    arrays->offd_i = std::move(offd_i_);
    arrays->offd_j = std::move(offd_j_);
    arrays->offd_a.assign(std::max<std::size_t>(num_offd_, 1), 0.0);
    if (arrays->offd_j.empty()) arrays->offd_j.push_back(0);  // a valid pointer for an empty block
    PetscCall(MatCreateMPIAIJWithSplitArrays(comm, m, m, PETSC_DETERMINE, PETSC_DETERMINE, arrays->diag_i.data(),
                                             arrays->diag_j.data(), arrays->diag_a.data(), arrays->offd_i.data(),
                                             arrays->offd_j.data(), arrays->offd_a.data(), J));
  }
  PetscCall(MatSetBlockSize(*J, bs));
  const char* prefix = nullptr;
  PetscCall(MatGetOptionsPrefix(like, &prefix));
  PetscCall(MatSetOptionsPrefix(*J, prefix));
  PetscContainer container;
  PetscCall(PetscContainerCreate(comm, &container));
  PetscCall(PetscContainerSetPointer(container, arrays.release()));
  PetscCall(PetscContainerSetUserDestroy(container, destroy_host_arrays));
  PetscCall(PetscObjectCompose(reinterpret_cast<PetscObject>(*J), "dipc_direct_arrays",
                               reinterpret_cast<PetscObject>(container)));
  PetscCall(PetscContainerDestroy(&container));
  PetscCall(check_host_pattern(*J, offd_columns));
  PetscFunctionReturn(0);
}

PetscErrorCode DirectMatrix::aij_blocks(Mat J, Mat* diag, Mat* offd, const PetscInt** garray) {
  PetscFunctionBeginUser;
  PetscBool mpi;
  PetscCall(PetscObjectTypeCompare(reinterpret_cast<PetscObject>(J), MATMPIAIJ, &mpi));
  *diag = J, *offd = nullptr;
  if (garray) *garray = nullptr;
  if (mpi) PetscCall(MatMPIAIJGetSeqAIJ(J, diag, offd, garray));
  PetscFunctionReturn(0);
}

PetscErrorCode DirectMatrix::check_host_pattern(Mat J, const std::vector<PetscInt>& offd_columns) const {
  PetscFunctionBeginUser;
  Mat A, B;
  const PetscInt* garray;
  PetscCall(aij_blocks(J, &A, &B, &garray));
  const PetscInt *ai, *aj, *bi = nullptr, *bj = nullptr;
  PetscScalar* unused;
  PetscCall(MatSeqAIJGetCSRAndMemType(A, &ai, &aj, &unused, nullptr));
  PetscInt m;
  PetscCall(MatGetLocalSize(A, &m, nullptr));
  bool same = static_cast<std::size_t>(ai[m]) == num_diag_;
  if (B) {
    PetscCall(MatSeqAIJGetCSRAndMemType(B, &bi, &bj, &unused, nullptr));
    same = same && static_cast<std::size_t>(bi[m]) == num_offd_;
    for (std::size_t k = 0; same && k < num_offd_; ++k) same = garray[bj[k]] == offd_columns[k];
  }
  PetscCheck(same, PETSC_COMM_SELF, PETSC_ERR_PLIB,
             "PETSc changed the pattern of the matrix made from dipc's arrays: the value positions do not hold");
  PetscFunctionReturn(0);
}

PetscErrorCode DirectMatrix::make_device_hypre(Mat like, const NodeBlockReduction* blocks,
                                               const ReservedBlocks* reserve, Mat* J) {
  PetscFunctionBeginUser;
#if PetscDefined(HAVE_HYPRE_DEVICE)
  static_assert(sizeof(HYPRE_Int) == sizeof(int), "the device writes hypre's column indices as int");
  MPI_Comm comm = PetscObjectComm(reinterpret_cast<PetscObject>(like));
  PetscInt m, bs;
  PetscCall(MatGetLocalSize(like, &m, nullptr));
  PetscCall(MatGetBlockSize(like, &bs));
  const PetscInt M = row_starts_.back(), begin = row_begin_;
  // The off-diagonal block's columns through its map: the distinct global columns, ascending.
  // Those of the rows the device writes are the blocks' outside the own nodes, which sit at
  // either end of a block row (its columns ascend). The rows go in chunks on the host threads,
  // each chunk's columns sorted and made distinct before they are joined.
  const std::int64_t node_begin = begin / 3, node_end = (begin + m) / 3;
  const auto block_columns = [&](std::size_t r0, std::size_t r1, std::vector<std::int64_t>& columns) {
    for (std::size_t r = r0; r < r1; ++r) {
      const std::int64_t s = device_block_row_[r];
      if (s < 0) continue;
      const int i = static_cast<int>(r % 3);
      const auto add = [&](std::size_t k) {
        for (int j = 0; j < 3; ++j)
          if (blocks->block_mask[k] >> (3 * i + j) & 1u) columns.push_back(3 * blocks->block_col[k] + j);
      };
      std::size_t k = blocks->row_start[s], e = blocks->row_start[s + 1];
      while (k < e && blocks->block_col[k] < node_begin) add(k++);
      while (e > k && blocks->block_col[e - 1] >= node_end) add(--e);
      if (!reserve) continue;
      for (std::size_t b = reserve_first_[r / 3]; b < reserve_first_[r / 3 + 1]; ++b) {
        const std::int64_t col_node = reserve->pair(b)[1];
        if (col_node >= node_begin && col_node < node_end) continue;
        for (int j = 0; j < 3; ++j)
          if (reserve->mask(b) >> (3 * i + j) & 1u) columns.push_back(3 * col_node + j);
      }
    }
    std::sort(columns.begin(), columns.end());
    columns.erase(std::unique(columns.begin(), columns.end()), columns.end());
  };
  std::vector<std::int64_t> col_map = parallel_collect<std::int64_t>(device_block_row_.size(), block_columns);
  for (const auto& entry : side_offd_) col_map.push_back(entry.second);
  std::sort(col_map.begin(), col_map.end());
  col_map.erase(std::unique(col_map.begin(), col_map.end()), col_map.end());
  PetscHYPREInitialize();
  PetscCallExternal(HYPRE_SetMemoryLocation, HYPRE_MEMORY_DEVICE);
  HYPRE_BigInt starts[2] = {static_cast<HYPRE_BigInt>(begin), static_cast<HYPRE_BigInt>(begin + m)};
  hypre_ParCSRMatrix* A = hypre_ParCSRMatrixCreate(comm, M, M, starts, starts, static_cast<HYPRE_Int>(col_map.size()),
                                                   static_cast<HYPRE_Int>(num_diag_),
                                                   static_cast<HYPRE_Int>(num_offd_));
  hypre_ParCSRMatrixInitialize_v2(A, HYPRE_MEMORY_DEVICE);
  hypre_CSRMatrix* diag = hypre_ParCSRMatrixDiag(A);
  hypre_CSRMatrix* offd = hypre_ParCSRMatrixOffd(A);
  const auto upload_ints = [](int* dst, const std::vector<PetscInt>& v) {
    const std::vector<int> converted(v.begin(), v.end());
    if (!converted.empty()) device::copy_to_device(dst, converted.data(), converted.size() * sizeof(int));
  };
  upload_ints(hypre_CSRMatrixI(diag), diag_i_);
  upload_ints(hypre_CSRMatrixI(offd), offd_i_);

  // The rows of node blocks alone, written on the device from compact copies of the blocks,
  // kept to write their values at every assembly (set_values); then the host's rows.
  PetscCall(upload_block_rows(blocks, reserve, m));
  if (block_rows_.num_rows) {
    device::Array<std::int64_t> d_col_map("matrix column map");
    d_col_map.upload(col_map);
    block_rows_.diag_i = hypre_CSRMatrixI(diag);
    block_rows_.offd_i = hypre_CSRMatrixI(offd);
    device::write_block_rows(block_rows_, d_col_map.data(), col_map.size(), hypre_CSRMatrixJ(diag),
                             hypre_CSRMatrixJ(offd));
    device::synchronize();  // before the column map goes
  }
  const auto scatter = [](auto* out, const std::vector<std::uint32_t>& index, const auto& value) {
    if (index.empty()) return;
    using T = typename std::decay_t<decltype(value)>::value_type;
    device::Array<std::uint32_t> d_index("matrix scatter indices");
    device::Array<T> d_value("matrix scatter values");
    d_index.upload(index);
    d_value.upload(value);
    device::scatter(out, d_index.data(), d_value.data(), index.size());
    device::synchronize();
  };
  {
    std::vector<std::uint32_t> index;
    std::vector<int> columns;
    for (const auto& [p, col] : side_diag_) index.push_back(p), columns.push_back(static_cast<int>(col));
    scatter(hypre_CSRMatrixJ(diag), index, columns);
    index.resize(side_offd_.size()), columns.resize(side_offd_.size());
    parallel_for(side_offd_.size(), [&](std::size_t k0, std::size_t k1) {
      for (std::size_t k = k0; k < k1; ++k) {
        index[k] = side_offd_[k].first;
        columns[k] = static_cast<int>(std::lower_bound(col_map.begin(), col_map.end(), side_offd_[k].second) -
                                      col_map.begin());
      }
    });
    scatter(hypre_CSRMatrixJ(offd), index, columns);
  }
  {
    // The host's rows' own entries: (entry, position) pairs, their values scattered at every
    // assembly.
    std::vector<std::uint32_t> entries, positions;
    entries.reserve(side_position_.size()), positions.reserve(side_position_.size());
    for (const auto& [entry, p] : side_position_) entries.push_back(entry), positions.push_back(p);
    d_side_entry_.upload(entries);
    d_side_position_.upload(positions);
  }
  if (num_diag_) device::zero(hypre_CSRMatrixData(diag), num_diag_ * sizeof(double));
  if (num_offd_) device::zero(hypre_CSRMatrixData(offd), num_offd_ * sizeof(double));
  HYPRE_BigInt* map = hypre_ParCSRMatrixColMapOffd(A);
  for (std::size_t k = 0; k < col_map.size(); ++k) map[k] = static_cast<HYPRE_BigInt>(col_map[k]);
  hypre_ParCSRMatrixCopyColMapOffdToDevice(A);
  hypre_MatvecCommPkgCreate(A);
  std::vector<PetscInt>().swap(diag_i_), std::vector<PetscInt>().swap(offd_i_);
  std::vector<std::int64_t>().swap(device_block_row_);
  side_diag_.clear(), side_offd_.clear(), side_position_.clear();
  PetscCall(MatCreateFromParCSR(A, MATHYPRE, PETSC_OWN_POINTER, J));
  PetscCall(MatSetBlockSize(*J, bs));
  const char* prefix = nullptr;
  PetscCall(MatGetOptionsPrefix(like, &prefix));
  PetscCall(MatSetOptionsPrefix(*J, prefix));
#else
  (void)like, (void)blocks, (void)J;
  SETERRQ(PETSC_COMM_SELF, PETSC_ERR_PLIB, "a device hypre matrix needs a PETSc whose hypre runs on the GPU");
#endif
  PetscFunctionReturn(0);
}

PetscErrorCode DirectMatrix::upload_block_rows(const NodeBlockReduction* blocks, const ReservedBlocks* reserve,
                                               PetscInt num_rows) {
  PetscFunctionBeginUser;
  const bool any = blocks && std::any_of(device_block_row_.begin(), device_block_row_.end(),
                                         [](std::int64_t s) { return s >= 0; });
  block_rows_.num_rows = 0;  // no rows to write until the arrays below are in place
  if (!any) {
    for (auto* a : {&d_block_row_start_, &d_block_col_, &d_block_start_}) a->resize(0);
    d_block_row_.resize(0), d_block_mask_.resize(0);
    blocks_id_ = 0;
    PetscFunctionReturn(0);
  }
  const std::vector<std::int32_t> block_row(device_block_row_.begin(), device_block_row_.end());
  d_block_row_.upload(block_row);
  // The element blocks are the same for a run's matrices (only which rows are blocks alone
  // changes with the contact entries): narrowed and copied once, not at every new pattern
  // (27.5M blocks at 1M hexes).
  if (blocks->id != blocks_id_) PetscCall(upload_blocks(*blocks));
  // The reserve's blocks of each own node (the reserve itself is on the device already).
  block_rows_.reserve_first = nullptr;
  if (reserve) {
    d_reserve_first_.upload(reserve_first_);
    block_rows_.reserve_first = d_reserve_first_.data();
    block_rows_.reserve_col = reserve->device_cols();
    block_rows_.reserve_mask = reserve->device_masks();
    block_rows_.reserve_start = reserve->device_starts();
  }
  block_rows_.num_rows = static_cast<std::size_t>(num_rows);
  block_rows_.row_begin = row_begin_;
  block_rows_.block_row = d_block_row_.data();
  PetscFunctionReturn(0);
}

void DirectMatrix::share_blocks(std::uint64_t blocks_id, const SharedBlocks& shared) {
  const bool all = shared.mask && shared.start && shared.row_start && shared.col;
  const std::uint64_t id = all ? blocks_id : 0;
  if (id == shared_id_ && shared.mask == shared_.mask && shared.start == shared_.start &&
      shared.row_start == shared_.row_start && shared.col == shared_.col)
    return;
  shared_id_ = id;
  shared_ = shared;
  blocks_id_ = 0;  // changed: the next create() takes the shared arrays or makes its own again
}

PetscErrorCode DirectMatrix::upload_blocks(const NodeBlockReduction& blocks) {
  PetscFunctionBeginUser;
  // 32 bits hold them: a rank's blocks stay below its entries, which send_remote_entries keeps
  // below 2^32, and its node block rows below 2^31; the column nodes are checked.
  if (blocks.id == shared_id_) {
    for (auto* a : {&d_block_row_start_, &d_block_col_, &d_block_start_}) a->resize(0);
    d_block_mask_.resize(0);
    block_rows_.mask = shared_.mask, block_rows_.start = shared_.start;
    block_rows_.row_start = shared_.row_start, block_rows_.col = shared_.col;
  } else {
    try {
      d_block_row_start_.upload(blocks.row_start_32());
      d_block_col_.upload(blocks.block_col_32());
      d_block_start_.upload(blocks.block_start_32());
    } catch (const std::length_error& e) {
      SETERRQ(PETSC_COMM_SELF, PETSC_ERR_SUP, "%s: run on more ranks", e.what());
    }
    d_block_mask_.upload(blocks.block_mask);
    block_rows_.mask = d_block_mask_.data(), block_rows_.start = d_block_start_.data();
    block_rows_.row_start = d_block_row_start_.data(), block_rows_.col = d_block_col_.data();
  }
  blocks_id_ = blocks.id;
  PetscFunctionReturn(0);
}

PetscErrorCode DirectMatrix::hypre_values(Mat J, double** diag, double** offd, const int** diag_i,
                                          const int** offd_i) const {
  PetscFunctionBeginUser;
#if PetscDefined(HAVE_HYPRE_DEVICE)
  hypre_ParCSRMatrix* A = nullptr;
  PetscCall(MatHYPREGetParCSR(J, &A));
  *diag = hypre_CSRMatrixData(hypre_ParCSRMatrixDiag(A));
  *offd = hypre_CSRMatrixData(hypre_ParCSRMatrixOffd(A));
  *diag_i = hypre_CSRMatrixI(hypre_ParCSRMatrixDiag(A));
  *offd_i = hypre_CSRMatrixI(hypre_ParCSRMatrixOffd(A));
#else
  (void)J, (void)diag, (void)offd, (void)diag_i, (void)offd_i;
#endif
  PetscFunctionReturn(0);
}

PetscErrorCode DirectMatrix::set_values(Mat J, const double* values) {
  PetscFunctionBeginUser;
  const std::size_t nd = num_diag_, ns = slot_position_.size();
  if (kind_ == Kind::device_hypre) {
    d_slot_sums_.resize(ns);
    remote_.sum_to_device(values, d_slot_sums_.data());
    double *diag = nullptr, *offd = nullptr;
    PetscCall(hypre_values(J, &diag, &offd, &block_rows_.diag_i, &block_rows_.offd_i));
    // Block rows, the host's rows and the received slots (which lie in the host's rows) are
    // disjoint entries of the matrix: the three writes do not meet.
    device::write_block_row_values(block_rows_, values, diag, offd);
    device::scatter_split(values, d_side_entry_.data(), d_side_position_.data(), d_side_entry_.size(), diag, nd, offd);
    if (ns) device::add_split(d_slot_sums_.data(), d_slot_position_.data(), d_slot_keep_.data(), ns, diag, nd, offd);
    device::synchronize();
  } else {
    slot_sums_.resize(ns);
    remote_.sum(values, slot_sums_.data());
    // The blocks' value arrays as PETSc holds them (the ones given at creation).
    Mat A, B;
    PetscCall(aij_blocks(J, &A, &B, nullptr));
    PetscScalar *diag, *offd = nullptr;
    PetscCall(MatSeqAIJGetArray(A, &diag));
    if (B) PetscCall(MatSeqAIJGetArray(B, &offd));
    const auto at = [&](std::uint32_t p) -> double& { return p < nd ? diag[p] : offd[p - nd]; };
    for (std::size_t k = 0; k < num_entries_; ++k)
      if (position_[k] != kRemote) at(position_[k]) = values[k];
    for (std::size_t s = 0; s < ns; ++s) {
      double& v = at(slot_position_[s]);
      v = (slot_keep_[s] ? v : 0.0) + slot_sums_[s];
    }
    PetscCall(MatSeqAIJRestoreArray(A, &diag));
    if (B) PetscCall(MatSeqAIJRestoreArray(B, &offd));
  }
  // The values changed behind PETSc's back: a new state, so that preconditioners set up again.
  PetscCall(PetscObjectStateIncrease(reinterpret_cast<PetscObject>(J)));
  PetscFunctionReturn(0);
}

}  // namespace dipc
