// Collective HDF5 helpers shared by the output writer and the checkpoint file: silencing HDF5's
// error printing (its message goes into an exception instead), turning its error stack into a
// sentence, and writing or reading one rank's contiguous block of rows of a dataset with
// MPI-IO collective transfers. Every function returns an error message, empty on success; the
// callers make a failure on any rank every rank's failure (collective_error.hpp).
#pragma once
#include <hdf5.h>
#include <mpi.h>

#include <cstdint>
#include <string>

namespace dipc {

// Turns off HDF5's automatic error-stack printing for the object's lifetime (the caller's
// handler is restored after); the stack itself stays available to hdf5_error_text().
class QuietHdf5Errors {
 public:
  QuietHdf5Errors();
  ~QuietHdf5Errors();
  QuietHdf5Errors(const QuietHdf5Errors&) = delete;
  QuietHdf5Errors& operator=(const QuietHdf5Errors&) = delete;

 private:
  H5E_auto2_t func_ = nullptr;
  void* data_ = nullptr;
};

// The outermost and innermost descriptions on HDF5's error stack, e.g. "unable to create
// file: unable to open file: name = '...', errno = 2, error message = 'No such file...'".
std::string hdf5_error_text();
// "<what> in '<path>': <hdf5_error_text()>".
std::string hdf5_failure(const std::string& what, const std::string& path);

// One rank's contiguous block of rows [row_offset, row_offset + local_rows) of a
// global_rows x columns dataset (columns == 0: one-dimensional).
struct RowBlock {
  hsize_t global_rows, columns, row_offset, local_rows;
};

// Creates `dataset_path` under `parent` and writes this rank's block collectively (every rank
// calls it, a rank without rows too).
std::string write_rows(hid_t parent, const std::string& dataset_path, hid_t file_type, hid_t memory_type,
                       const RowBlock& block, const void* data, const std::string& h5_path);
// Reads this rank's block of an existing dataset collectively; the dataset's dimensions must be
// block.global_rows x block.columns.
std::string read_rows(hid_t parent, const std::string& dataset_path, hid_t memory_type, const RowBlock& block,
                      void* data, const std::string& h5_path);

// File access through MPI-IO on `comm` with collective metadata operations (HDF5 >= 1.10
// parallel I/O guidance: one rank writes each metadata block instead of all racing on it).
hid_t mpio_file_access(MPI_Comm comm);

}  // namespace dipc
