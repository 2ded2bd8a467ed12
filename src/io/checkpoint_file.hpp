// CheckpointFile: one HDF5 file holding everything a run needs to continue (written and read
// collectively by all ranks through MPI-IO). Layout, readable with h5py/h5dump:
//   /  attributes  format = "dipc checkpoint", version = 1, the run's named integers, reals
//                  and texts (step, time, kappa, ..., see app/checkpoint.cpp)
//   /nodes/<field> N x 3 double, rows in the INPUT mesh's node numbering (so that any rank
//                  count, any partition, can read it); attribute "checksum"
// The checksum is a sum over entries of a hash of (row, column, bits of the value), modulo
// 2^64: it does not depend on how the rows were split over ranks, and a changed value changes
// it with overwhelming probability (HDF5 itself does not check raw data).
// A file is written as <path>.tmp and renamed to <path> once complete and closed, so a
// checkpoint under its final name is always whole.
#pragma once
#include <mpi.h>

#include <cstdint>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace dipc {

inline constexpr int kCheckpointVersion = 1;

// Why a checkpoint was refused; the message names the file and says which of these it is.
class CheckpointError : public std::runtime_error {
 public:
  enum class Kind { unreadable, truncated, corrupt, foreign, version, mismatched };
  CheckpointError(Kind kind, const std::string& message) : std::runtime_error(message), kind_(kind) {}
  Kind kind() const { return kind_; }

 private:
  Kind kind_;
};

struct CheckpointContents {
  std::map<std::string, std::int64_t> integers;
  std::map<std::string, double> reals;
  std::map<std::string, std::string> texts;
  // This rank's block of the input numbering: rows [node_offset, node_offset + num_block_nodes)
  // of num_global_nodes; each field holds 3 values per row.
  std::int64_t num_global_nodes = 0, node_offset = 0;
  int num_block_nodes = 0;
  std::map<std::string, std::vector<double>> node_fields;
};

// Collective. Writes `contents` to <path>.tmp, closes it and renames it to `path` (rank 0).
// Throws std::runtime_error naming the file on every rank when any rank fails.
void write_checkpoint_file(MPI_Comm comm, const std::string& path, const CheckpointContents& contents);

// Collective. Reads the attributes named in `contents` (their keys; values are replaced) and
// this rank's block of each node field named there, checking every checksum. Throws
// CheckpointError (the same on every rank): not HDF5 or no dipc format attribute (foreign),
// shorter than HDF5 says (truncated), unreadable metadata or a wrong checksum (corrupt),
// another version, or a missing attribute or dataset, or other row counts (mismatched).
void read_checkpoint_file(MPI_Comm comm, const std::string& path, CheckpointContents* contents);

}  // namespace dipc
