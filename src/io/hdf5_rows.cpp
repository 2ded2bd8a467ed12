// Collective HDF5 helpers (see hdf5_rows.hpp).
#include "io/hdf5_rows.hpp"

#include <algorithm>

#include "io/hdf5_handle.hpp"

namespace dipc {

QuietHdf5Errors::QuietHdf5Errors() {
  H5Eget_auto2(H5E_DEFAULT, &func_, &data_);
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
}

QuietHdf5Errors::~QuietHdf5Errors() { H5Eset_auto2(H5E_DEFAULT, func_, data_); }

std::string hdf5_error_text() {
  struct Ends {
    std::string first, last;
  } ends;
  H5Ewalk2(
      H5E_DEFAULT, H5E_WALK_DOWNWARD,
      [](unsigned, const H5E_error2_t* e, void* data) -> herr_t {
        auto* out = static_cast<Ends*>(data);
        if (e->desc != nullptr && *e->desc != '\0') {
          if (out->first.empty()) out->first = e->desc;
          out->last = e->desc;
        }
        return 0;
      },
      &ends);
  if (ends.first.empty()) return "HDF5 error";
  return ends.first == ends.last ? ends.first : ends.first + ": " + ends.last;
}

std::string hdf5_failure(const std::string& what, const std::string& path) {
  return what + " in '" + path + "': " + hdf5_error_text();
}

namespace {

// Selects this rank's rows in file_space and sizes the matching memory space; a rank with no
// rows still takes part in the collective transfer, with empty selections.
std::string select_block(const RowBlock& block, hid_t file_space, Hdf5Handle* memory_space, const std::string& what,
                         const std::string& h5_path) {
  const int rank = block.columns == 0 ? 1 : 2;
  const hsize_t start[2] = {block.row_offset, 0};
  const hsize_t count[2] = {block.local_rows, block.columns};
  const hsize_t memory_dims[2] = {block.local_rows > 0 ? block.local_rows : 1, block.columns};
  *memory_space = Hdf5Handle(H5Screate_simple(rank, memory_dims, nullptr), H5Sclose);
  if (!memory_space->valid()) return hdf5_failure("cannot create memory dataspace for " + what, h5_path);
  herr_t status = 0;
  if (block.local_rows > 0) {
    status = H5Sselect_hyperslab(file_space, H5S_SELECT_SET, start, nullptr, count, nullptr);
  } else {
    status = std::min(H5Sselect_none(file_space), H5Sselect_none(memory_space->get()));
  }
  if (status < 0) return hdf5_failure("cannot select rows of " + what, h5_path);
  return {};
}

std::string collective_transfer(Hdf5Handle* transfer, const std::string& what, const std::string& h5_path) {
  *transfer = Hdf5Handle(H5Pcreate(H5P_DATASET_XFER), H5Pclose);
  if (!transfer->valid() || H5Pset_dxpl_mpio(transfer->get(), H5FD_MPIO_COLLECTIVE) < 0)
    return hdf5_failure("cannot set collective transfer for " + what, h5_path);
  return {};
}

}  // namespace

std::string write_rows(hid_t parent, const std::string& dataset_path, hid_t file_type, hid_t memory_type,
                       const RowBlock& block, const void* data, const std::string& h5_path) {
  const int rank = block.columns == 0 ? 1 : 2;
  const hsize_t global_dims[2] = {block.global_rows, block.columns};
  Hdf5Handle file_space(H5Screate_simple(rank, global_dims, nullptr), H5Sclose);
  Hdf5Handle dcpl(H5Pcreate(H5P_DATASET_CREATE), H5Pclose);
  if (!file_space.valid() || !dcpl.valid()) return hdf5_failure("cannot create dataspace for " + dataset_path, h5_path);
  // Every element is written by some rank, so HDF5's fill pass would be a wasted second write.
  H5Pset_fill_time(dcpl.get(), H5D_FILL_TIME_NEVER);
  Hdf5Handle dataset(H5Dcreate2(parent, dataset_path.c_str(), file_type, file_space.get(), H5P_DEFAULT, dcpl.get(),
                                H5P_DEFAULT),
                     H5Dclose);
  if (!dataset.valid()) return hdf5_failure("cannot create dataset " + dataset_path, h5_path);
  Hdf5Handle memory_space, transfer;
  std::string error = select_block(block, file_space.get(), &memory_space, dataset_path, h5_path);
  if (error.empty()) error = collective_transfer(&transfer, dataset_path, h5_path);
  if (!error.empty()) return error;
  if (H5Dwrite(dataset.get(), memory_type, memory_space.get(), file_space.get(), transfer.get(), data) < 0)
    return hdf5_failure("cannot write dataset " + dataset_path, h5_path);
  return {};
}

std::string read_rows(hid_t parent, const std::string& dataset_path, hid_t memory_type, const RowBlock& block,
                      void* data, const std::string& h5_path) {
  Hdf5Handle dataset(H5Dopen2(parent, dataset_path.c_str(), H5P_DEFAULT), H5Dclose);
  if (!dataset.valid()) return hdf5_failure("cannot open dataset " + dataset_path, h5_path);
  Hdf5Handle file_space(H5Dget_space(dataset.get()), H5Sclose);
  const int expected_rank = block.columns == 0 ? 1 : 2;
  hsize_t dims[2] = {0, 0};
  if (!file_space.valid() || H5Sget_simple_extent_ndims(file_space.get()) != expected_rank ||
      H5Sget_simple_extent_dims(file_space.get(), dims, nullptr) < 0 || dims[0] != block.global_rows ||
      (expected_rank == 2 && dims[1] != block.columns))
    return "dataset " + dataset_path + " in '" + h5_path + "' has dimensions " + std::to_string(dims[0]) + " x " +
           std::to_string(dims[1]) + ", expected " + std::to_string(block.global_rows) + " x " +
           std::to_string(block.columns);
  Hdf5Handle memory_space, transfer;
  std::string error = select_block(block, file_space.get(), &memory_space, dataset_path, h5_path);
  if (error.empty()) error = collective_transfer(&transfer, dataset_path, h5_path);
  if (!error.empty()) return error;
  if (H5Dread(dataset.get(), memory_type, memory_space.get(), file_space.get(), transfer.get(), data) < 0)
    return hdf5_failure("cannot read dataset " + dataset_path, h5_path);
  return {};
}

hid_t mpio_file_access(MPI_Comm comm) {
  hid_t access = H5Pcreate(H5P_FILE_ACCESS);
  if (access < 0) return access;
  if (H5Pset_fapl_mpio(access, comm, MPI_INFO_NULL) < 0 || H5Pset_coll_metadata_write(access, true) < 0 ||
      H5Pset_all_coll_metadata_ops(access, true) < 0) {
    H5Pclose(access);
    return H5I_INVALID_HID;
  }
  return access;
}

}  // namespace dipc
