// XdmfWriter: collective XDMF + HDF5 output (see xdmf_writer.hpp). Every stage ends with a
// collective error check so that all ranks throw together, and HDF5's own error printing is
// silenced while the writer works: its message goes into the exception instead.
#include "io/xdmf_writer.hpp"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "io/collective_error.hpp"
#include "io/xdmf_text.hpp"

namespace dipc {
namespace {

// Turns off HDF5's automatic error-stack printing while a writer call runs (restoring the
// caller's handler after); the stack itself stays available to hdf5_error_text().
class QuietHdf5Errors {
 public:
  QuietHdf5Errors() {
    H5Eget_auto2(H5E_DEFAULT, &func_, &data_);
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  }
  ~QuietHdf5Errors() { H5Eset_auto2(H5E_DEFAULT, func_, data_); }
  QuietHdf5Errors(const QuietHdf5Errors&) = delete;
  QuietHdf5Errors& operator=(const QuietHdf5Errors&) = delete;

 private:
  H5E_auto2_t func_ = nullptr;
  void* data_ = nullptr;
};

// The outermost and innermost descriptions on HDF5's error stack, e.g. "unable to create
// file: unable to open file: name = '...', errno = 2, error message = 'No such file...'".
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

// One rank's contiguous block of rows [row_offset, row_offset + local_rows) of a
// global_rows x columns dataset (columns == 0: one-dimensional), written collectively.
struct RowBlock {
  hsize_t global_rows, columns, row_offset, local_rows;
};

// Returns an error message, empty on success.
std::string write_rows(hid_t parent, const std::string& dataset_path, hid_t file_type, hid_t memory_type,
                       const RowBlock& block, const void* data, const std::string& h5_path) {
  const int rank = block.columns == 0 ? 1 : 2;
  const hsize_t global_dims[2] = {block.global_rows, block.columns};
  Hdf5Handle file_space(H5Screate_simple(rank, global_dims, nullptr), H5Sclose);
  Hdf5Handle dcpl(H5Pcreate(H5P_DATASET_CREATE), H5Pclose);
  if (!file_space.valid() || !dcpl.valid()) return hdf5_failure("cannot create dataspace for " + dataset_path, h5_path);
  // Every element is written by some rank, so HDF5's fill pass would be a wasted second write.
  H5Pset_fill_time(dcpl.get(), H5D_FILL_TIME_NEVER);
  Hdf5Handle dataset(H5Dcreate2(parent, dataset_path.c_str(), file_type, file_space.get(), H5P_DEFAULT,
                                dcpl.get(), H5P_DEFAULT),
                     H5Dclose);
  if (!dataset.valid()) return hdf5_failure("cannot create dataset " + dataset_path, h5_path);

  const hsize_t start[2] = {block.row_offset, 0};
  const hsize_t count[2] = {block.local_rows, block.columns};
  // A rank with no rows still takes part in the collective write, with empty selections.
  const hsize_t memory_dims[2] = {block.local_rows > 0 ? block.local_rows : 1, block.columns};
  Hdf5Handle memory_space(H5Screate_simple(rank, memory_dims, nullptr), H5Sclose);
  if (!memory_space.valid()) return hdf5_failure("cannot create memory dataspace for " + dataset_path, h5_path);
  herr_t status = 0;
  if (block.local_rows > 0) {
    status = H5Sselect_hyperslab(file_space.get(), H5S_SELECT_SET, start, nullptr, count, nullptr);
  } else {
    status = std::min(H5Sselect_none(file_space.get()), H5Sselect_none(memory_space.get()));
  }
  if (status < 0) return hdf5_failure("cannot select rows of " + dataset_path, h5_path);

  Hdf5Handle transfer(H5Pcreate(H5P_DATASET_XFER), H5Pclose);
  if (!transfer.valid() || H5Pset_dxpl_mpio(transfer.get(), H5FD_MPIO_COLLECTIVE) < 0) {
    return hdf5_failure("cannot set collective transfer for " + dataset_path, h5_path);
  }
  if (H5Dwrite(dataset.get(), memory_type, memory_space.get(), file_space.get(), transfer.get(), data) < 0) {
    return hdf5_failure("cannot write dataset " + dataset_path, h5_path);
  }
  return {};
}

std::string missing_array(const char* what, int count) {
  return std::string("XdmfWriter: ") + what + " is null but this rank has " + std::to_string(count) + " entries";
}

// The ranks' blocks must tile [0, global) in rank order: offset == sum of lower ranks' counts.
std::string check_tiling(MPI_Comm comm, const char* what, std::int64_t global, std::int64_t offset,
                         std::int64_t count) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  std::int64_t expected_offset = 0, total = 0, global_min = 0, global_max = 0;
  MPI_Exscan(&count, &expected_offset, 1, MPI_INT64_T, MPI_SUM, comm);
  if (rank == 0) expected_offset = 0;
  MPI_Allreduce(&count, &total, 1, MPI_INT64_T, MPI_SUM, comm);
  MPI_Allreduce(&global, &global_min, 1, MPI_INT64_T, MPI_MIN, comm);
  MPI_Allreduce(&global, &global_max, 1, MPI_INT64_T, MPI_MAX, comm);
  const std::string prefix = std::string("XdmfWriter: ") + what + ": ";
  if (global_min != global_max) return prefix + "ranks disagree on the global count";
  if (count < 0) return prefix + "negative local count " + std::to_string(count);
  if (total != global) {
    return prefix + "local counts sum to " + std::to_string(total) + ", global count is " + std::to_string(global);
  }
  if (global < 1) return prefix + "the mesh is empty";
  if (offset != expected_offset) {
    return prefix + "offset " + std::to_string(offset) + " on rank " + std::to_string(rank) +
           " should be " + std::to_string(expected_offset) + " (blocks must follow rank order)";
  }
  return {};
}

}  // namespace

XdmfWriter::XdmfWriter(const std::string& directory, const std::string& name, const OutputMesh& mesh)
    : comm_(mesh.comm),
      directory_(directory.empty() ? "." : directory),
      name_(name),
      num_global_nodes_(mesh.num_global_nodes),
      node_offset_(mesh.node_offset),
      num_global_elements_(mesh.num_global_elements),
      element_offset_(mesh.element_offset),
      num_owned_nodes_(mesh.num_owned_nodes),
      num_elements_(mesh.num_elements) {
  if (comm_ == MPI_COMM_NULL) throw std::runtime_error("XdmfWriter: OutputMesh::comm is MPI_COMM_NULL");
  MPI_Comm_rank(comm_, &rank_);
  const QuietHdf5Errors quiet;

  std::string error = check_tiling(comm_, "nodes", num_global_nodes_, node_offset_, num_owned_nodes_);
  if (error.empty()) error = check_tiling(comm_, "elements", num_global_elements_, element_offset_, num_elements_);
  if (error.empty() && num_owned_nodes_ > 0 && mesh.owned_coordinates == nullptr) {
    error = missing_array("owned_coordinates", num_owned_nodes_);
  }
  if (error.empty() && num_elements_ > 0 && (mesh.element_nodes == nullptr || mesh.element_body == nullptr)) {
    error = missing_array("element_nodes or element_body", num_elements_);
  }
  throw_if_failed_anywhere(comm_, error);

  if (rank_ == 0) {
    std::error_code ec;
    std::filesystem::create_directories(directory_, ec);
    if (ec || !std::filesystem::is_directory(directory_)) {
      error = "cannot create output directory '" + directory_ + "'" + (ec ? ": " + ec.message() : std::string());
    }
  }
  throw_if_failed_anywhere(comm_, error);

  const std::string h5 = h5_path();
  {
    Hdf5Handle access(H5Pcreate(H5P_FILE_ACCESS), H5Pclose);
    // Collective metadata writes: one rank writes each metadata block instead of all
    // ranks racing on it (HDF5 >= 1.10 parallel I/O guidance).
    if (!access.valid() || H5Pset_fapl_mpio(access.get(), comm_, MPI_INFO_NULL) < 0 ||
        H5Pset_coll_metadata_write(access.get(), true) < 0 || H5Pset_all_coll_metadata_ops(access.get(), true) < 0) {
      error = hdf5_failure("cannot set up MPI-IO file access", h5);
    } else {
      file_ = Hdf5Handle(H5Fcreate(h5.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, access.get()), H5Fclose);
      if (!file_.valid()) error = "cannot create HDF5 file '" + h5 + "': " + hdf5_error_text();
    }
  }
  throw_if_failed_anywhere(comm_, error);

  for (const char* group : {"/mesh", "/steps"}) {
    Hdf5Handle g(H5Gcreate2(file_.get(), group, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose);
    if (!g.valid() && error.empty()) error = hdf5_failure(std::string("cannot create group ") + group, h5);
  }
  throw_if_failed_anywhere(comm_, error);

  const auto nodes = RowBlock{hsize_t(num_global_nodes_), 3, hsize_t(node_offset_), hsize_t(num_owned_nodes_)};
  const auto hex = RowBlock{hsize_t(num_global_elements_), 8, hsize_t(element_offset_), hsize_t(num_elements_)};
  const auto cells = RowBlock{hsize_t(num_global_elements_), 0, hsize_t(element_offset_), hsize_t(num_elements_)};
  const std::vector<int> owner(static_cast<std::size_t>(num_elements_), rank_);
  throw_if_failed_anywhere(comm_, write_rows(file_.get(), "/mesh/coordinates", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE,
                                             nodes, mesh.owned_coordinates, h5));
  throw_if_failed_anywhere(comm_, write_rows(file_.get(), "/mesh/topology", H5T_STD_I64LE, H5T_NATIVE_INT64, hex,
                                             mesh.element_nodes, h5));
  throw_if_failed_anywhere(comm_, write_rows(file_.get(), "/mesh/rank", H5T_STD_I32LE, H5T_NATIVE_INT, cells,
                                             owner.data(), h5));
  throw_if_failed_anywhere(comm_, write_rows(file_.get(), "/mesh/body", H5T_STD_I32LE, H5T_NATIVE_INT, cells,
                                             mesh.element_body, h5));
  if (H5Fflush(file_.get(), H5F_SCOPE_GLOBAL) < 0) error = hdf5_failure("cannot flush", h5);
  throw_if_failed_anywhere(comm_, error);
  write_xdmf_on_rank0();
}

XdmfWriter::~XdmfWriter() {
  const QuietHdf5Errors quiet;
  file_.reset();
}

std::string XdmfWriter::h5_path() const { return (std::filesystem::path(directory_) / (name_ + ".h5")).string(); }

std::string XdmfWriter::xdmf_path() const {
  return (std::filesystem::path(directory_) / (name_ + ".xmf")).string();
}

void XdmfWriter::write_step(double time, const double* owned_displacement, const double* owned_velocity,
                            const double* element_volume_ratio) {
  const QuietHdf5Errors quiet;
  const std::string h5 = h5_path();
  std::string error;
  if (num_owned_nodes_ > 0 && (owned_displacement == nullptr || owned_velocity == nullptr)) {
    error = missing_array("owned_displacement or owned_velocity", num_owned_nodes_);
  } else if (num_elements_ > 0 && element_volume_ratio == nullptr) {
    error = missing_array("element_volume_ratio", num_elements_);
  }
  double time_range[2] = {-time, time};
  MPI_Allreduce(MPI_IN_PLACE, time_range, 2, MPI_DOUBLE, MPI_MAX, comm_);
  if (error.empty() && -time_range[0] != time_range[1]) {
    error = "XdmfWriter: ranks disagree on the time of step " + std::to_string(step_times_.size());
  }
  throw_if_failed_anywhere(comm_, error);

  const std::string step = "/steps/" + std::to_string(step_times_.size());
  Hdf5Handle group(H5Gcreate2(file_.get(), step.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose);
  if (!group.valid()) {
    error = hdf5_failure("cannot create group " + step, h5);
  } else {
    Hdf5Handle scalar(H5Screate(H5S_SCALAR), H5Sclose);
    Hdf5Handle attribute(
        H5Acreate2(group.get(), "time", H5T_IEEE_F64LE, scalar.get(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
    if (!attribute.valid() || H5Awrite(attribute.get(), H5T_NATIVE_DOUBLE, &time) < 0) {
      error = hdf5_failure("cannot write attribute " + step + "/time", h5);
    }
  }
  throw_if_failed_anywhere(comm_, error);

  const auto nodes = RowBlock{hsize_t(num_global_nodes_), 3, hsize_t(node_offset_), hsize_t(num_owned_nodes_)};
  const auto cells = RowBlock{hsize_t(num_global_elements_), 0, hsize_t(element_offset_), hsize_t(num_elements_)};
  throw_if_failed_anywhere(comm_, write_rows(group.get(), "displacement", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, nodes,
                                             owned_displacement, h5));
  throw_if_failed_anywhere(comm_, write_rows(group.get(), "velocity", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, nodes,
                                             owned_velocity, h5));
  throw_if_failed_anywhere(comm_, write_rows(group.get(), "volume_ratio", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, cells,
                                             element_volume_ratio, h5));
  // The step must be on disk before the .xmf points at it.
  if (H5Fflush(file_.get(), H5F_SCOPE_GLOBAL) < 0) error = hdf5_failure("cannot flush", h5);
  throw_if_failed_anywhere(comm_, error);

  step_times_.push_back(time);
  write_xdmf_on_rank0();
}

void XdmfWriter::write_xdmf_on_rank0() const {
  std::string error;
  if (rank_ == 0) {
    const std::string path = xdmf_path();
    const std::string temporary = path + ".tmp";
    const XdmfLayout layout{name_ + ".h5", num_global_nodes_, num_global_elements_};
    {
      std::ofstream out(temporary, std::ios::trunc);
      out << xdmf_document(layout, step_times_);
      out.close();
      if (!out) error = "cannot write '" + temporary + "'";
    }
    // rename(2) replaces the old file atomically: readers see the old or the new .xmf, never
    // a partial one.
    std::error_code ec;
    if (error.empty()) std::filesystem::rename(temporary, path, ec);
    if (ec) error = "cannot rename '" + temporary + "' to '" + path + "': " + ec.message();
  }
  throw_if_failed_anywhere(comm_, error);
}

}  // namespace dipc
