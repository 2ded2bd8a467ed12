// DirectMatrix: the Hessian's PETSc matrix built from dipc's own list of entries, its values
// written straight into the matrix's arrays.
//
// PETSc's COO path (MatSetPreallocationCOO / MatSetValuesCOO) sorts every entry it is given and
// keeps a permutation and offsets (16 B) per entry beside the matrix. At 125,000 hexes on one
// rank it was 78 % of the setup (3.6 of 4.6 s) and at 1M hexes on one H100 most of the 28 s
// (docs/performance.md, "Setup"). Here each rank sorts only its rows' short column lists once,
// hands PETSc (or hypre) arrays it does not copy, and keeps one 4 B position per entry (on the
// device, only for the rows that are not node blocks alone: see below).
//
// Entries of rows another rank owns (the ghost rows of a rank's elements) go to their owner
// once at creation, which adds them to its pattern; at every assembly their values travel to
// the owner (RemoteEntrySums) and are added to its own (the owner's value first, then the
// other ranks' in rank order: a fixed order, so runs on the same ranks give the same bits).
//
// Two kinds of matrix are built this way (every other type keeps the COO path):
//   host_aij      MATSEQAIJ (MatCreateSeqAIJWithArrays) or MATMPIAIJ
//                 (MatCreateMPIAIJWithSplitArrays): columns ascending in each row;
//   device_hypre  MATHYPRE whose hypre runs on the GPU: a hypre ParCSR matrix made on the
//                 device (MatCreateFromParCSR), the diagonal first in each row of its diagonal
//                 block as hypre's smoothers expect, the off-diagonal block's columns numbered
//                 through its ascending column map. The rows made of node blocks alone, the
//                 element forms' and the contact reserve's (nearly all) are written on the
//                 device (device::write_block_rows), and their values at every assembly by the
//                 same walk over the blocks (the element part's arrays shared, against 4 B per
//                 entry, 36 per full block); the host counts them and writes the others (rows
//                 with entries of the list or from other ranks), whose entries keep their
//                 positions.
// Values are given in the entry order of create(): host memory for host_aij, device memory for
// device_hypre.
#pragma once
#include <petscmat.h>

#include <cstddef>
#include <cstdint>
#include <vector>

#include "assembly/cuda/block_rows.hpp"
#include "assembly/large_page_vector.hpp"
#include "assembly/node_block_reduction.hpp"
#include "assembly/remote_entry_sums.hpp"
#include "assembly/reserved_blocks.hpp"
#include "device/device_runtime.hpp"

namespace dipc {

class DirectMatrix {
 public:
  enum class Kind { coo, host_aij, device_hypre };
  // The kind that serves J (type set, not yet preallocated); coo where none does.
  static Kind kind_of(Mat J);

  DirectMatrix() = default;
  DirectMatrix(const DirectMatrix&) = delete;
  DirectMatrix& operator=(const DirectMatrix&) = delete;

  // Collective. A new matrix *J of `kind` (not coo) over the rows and columns of `like` (sizes,
  // block size, options prefix), holding the rank's entries: those of the node blocks of
  // `blocks` (may be null) in its entry order (dof 3 node + component; the rank's rows then
  // must start and end at a node), then (rows[k], cols[k]), k < n, then those of the reserve's
  // blocks (may be null; numbered on from the list's end, with `blocks`). Global dof ids, no
  // pair twice on a rank, rows of any rank. The blocks are read as given, never expanded into
  // (row, col) lists: at 1M hexes those lists alone were 2 GB, and the contact reserve's of the
  // 1M stack 28M entries, sorted row by row on the host at every new matrix. For device_hypre
  // the reserve must be on the device (ReservedBlocks::upload). Replaces what an earlier
  // create() set up; the arrays of an earlier matrix live as long as that matrix.
  PetscErrorCode create(Mat like, Kind kind, const NodeBlockReduction* blocks, const ReservedBlocks* reserve,
                        const PetscInt* rows, const PetscInt* cols, std::size_t n, Mat* J);
  PetscErrorCode create(Mat like, Kind kind, const NodeBlockReduction* blocks, const PetscInt* rows,
                        const PetscInt* cols, std::size_t n, Mat* J) {
    return create(like, kind, blocks, nullptr, rows, cols, n, J);
  }
  PetscErrorCode create(Mat like, Kind kind, const PetscInt* rows, const PetscInt* cols, std::size_t n, Mat* J) {
    return create(like, kind, nullptr, nullptr, rows, cols, n, J);
  }
  // device_hypre: the node blocks' masks, 32-bit entry starts, row starts and column nodes of
  // the NodeBlockReduction blocks_id, on the device, where another part keeps them
  // (ElementBlockPart): later create()s of those blocks use them instead of copies of their own
  // (about 280 B per hex). They must outlive this matrix's use; a null pointer shares none.
  struct SharedBlocks {
    const std::uint16_t* mask = nullptr;
    const std::uint32_t* start = nullptr;
    const std::uint32_t* row_start = nullptr;
    const std::uint32_t* col = nullptr;
  };
  void share_blocks(std::uint64_t blocks_id, const SharedBlocks& shared);
  // Collective. J's values from values[k] for the entries k of create() (on the host for
  // host_aij, on the device for device_hypre). J must be the matrix create() made last.
  PetscErrorCode set_values(Mat J, const double* values);

 private:
  // The rank's rows [row_begin_, row_begin_ + num_rows) as CSR, the positions, and the exchange
  // of other ranks' rows.
  PetscErrorCode build_pattern(MPI_Comm comm, PetscInt num_rows, const NodeBlockReduction* blocks,
                               const ReservedBlocks* reserve, const PetscInt* rows, const PetscInt* cols,
                               std::size_t n);
  // build_pattern's steps (direct_matrix.cpp): the rank's rows' entries as they are gathered,
  // the entries of other ranks' rows sent to their owners, then two passes over the rows.
  struct RowEntries;
  struct ChunkCounts;
  PetscErrorCode send_remote_entries(MPI_Comm comm, RowEntries& entries,
                                     std::vector<std::vector<std::uint32_t>>* remote_entry);
  std::vector<ChunkCounts> count_row_columns(const RowEntries& entries);
  std::vector<std::uint32_t> write_rows(const RowEntries& entries, std::vector<ChunkCounts>& chunk);
  void finish_offd_positions();
  PetscErrorCode make_host_aij(Mat like, Mat* J);
  PetscErrorCode make_device_hypre(Mat like, const NodeBlockReduction* blocks, const ReservedBlocks* reserve, Mat* J);
  // device_hypre: J's value arrays and row starts on the device.
  PetscErrorCode hypre_values(Mat J, double** diag, double** offd, const int** diag_i, const int** offd_i) const;
  // host_aij: J's diagonal and off-diagonal blocks (offd null on a SEQAIJ) and the latter's
  // global columns.
  static PetscErrorCode aij_blocks(Mat J, Mat* diag, Mat* offd, const PetscInt** garray);
  // host_aij: checks that PETSc kept the pattern as given (the positions depend on it).
  PetscErrorCode check_host_pattern(Mat J, const std::vector<PetscInt>& offd_columns) const;

  Kind kind_ = Kind::coo;
  std::size_t num_entries_ = 0;
  std::vector<PetscInt> row_starts_;  // every rank's first row, and the number of rows at the end
  PetscInt row_begin_ = 0;
  // The pattern of this rank's rows (CSR): the diagonal block's columns relative to the first
  // owned column, the off-diagonal block's as global ids, each row's in the kind's order.
  std::vector<PetscInt> diag_i_, offd_i_, offd_j_;
  LargePageVector<PetscInt> diag_j_;
  // Per entry of create(): its position among the values (diagonal block, then off-diagonal
  // block), or kRemote where another rank owns its row.
  static constexpr std::uint32_t kRemote = 0xffffffffu;
  LargePageVector<std::uint32_t> position_;
  // device_hypre writes the rows made of node blocks alone on the device
  // (device::write_block_rows): per row, its node block row there (-1 for the other rows), and
  // the other rows' columns (position in the block, column) and own entries' (entry, position),
  // written by the host. position_, diag_j_ and offd_j_ then stay empty.
  std::vector<std::int64_t> device_block_row_;
  std::vector<std::pair<std::uint32_t, PetscInt>> side_diag_, side_offd_;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> side_position_;
  // Entries other ranks send here: one slot per distinct (row, column), its position, and
  // whether an entry of this rank is there too (then the slot's sum is added to it).
  std::vector<std::uint32_t> slot_position_;
  std::vector<std::uint8_t> slot_keep_;
  RemoteEntrySums remote_;  // the values of this rank's entries of other ranks' rows, to their slots
  std::size_t num_diag_ = 0, num_offd_ = 0;
  std::vector<double> slot_sums_;
  // device_hypre: the rows of node blocks alone are walked again at every assembly
  // (device::write_block_row_values) from 32-bit copies of the blocks (the masks and starts
  // shared where share_blocks gave them) instead of a 4 B position per entry; the host's rows'
  // own entries keep theirs.
  PetscErrorCode upload_block_rows(const NodeBlockReduction* blocks, const ReservedBlocks* reserve, PetscInt num_rows);
  PetscErrorCode upload_blocks(const NodeBlockReduction& blocks);
  std::uint64_t blocks_id_ = 0;  // the NodeBlockReduction the device copies below are of (0: none)
  std::uint64_t shared_id_ = 0;
  SharedBlocks shared_;
  device::BlockRows block_rows_;  // the arrays below (or the shared ones) and this rank's rows
  device::Array<std::int32_t> d_block_row_{"matrix block rows"};
  device::Array<std::uint32_t> d_block_row_start_{"matrix block row starts"}, d_block_col_{"matrix block columns"},
      d_block_start_{"matrix block entry starts"};
  device::Array<std::uint16_t> d_block_mask_{"matrix block masks"};
  // The reserve's blocks of each own node: [reserve_first_[q], reserve_first_[q + 1]) for own
  // node q, on the host while the pattern is built and on the device for the block rows.
  std::vector<std::uint32_t> reserve_first_;
  device::Array<std::uint32_t> d_reserve_first_{"matrix reserve row starts"};
  device::Array<std::uint32_t> d_side_entry_{"matrix host-row entries"}, d_side_position_{"matrix host-row positions"};
  device::Array<std::uint32_t> d_slot_position_{"matrix slot positions"};
  device::Array<std::uint8_t> d_slot_keep_{"matrix slot flags"};
  device::Array<double> d_slot_sums_{"matrix slot sums"};
};

}  // namespace dipc
