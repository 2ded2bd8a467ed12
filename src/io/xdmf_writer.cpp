// XdmfWriter: collective XDMF + HDF5 output (see xdmf_writer.hpp). Every stage ends with a
// collective error check so that all ranks throw together, and HDF5's own error printing is
// silenced while the writer works: its message goes into the exception instead.
#include "io/xdmf_writer.hpp"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "io/collective_error.hpp"
#include "io/hdf5_rows.hpp"
#include "io/xdmf_text.hpp"

namespace dipc {
namespace {

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

XdmfWriter::XdmfWriter(const std::string& directory, const std::string& name, const OutputMesh& mesh,
                       std::int64_t keep_steps)
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

  // Continue only a file that exists (rank 0 looks; every rank follows its answer).
  int existing = 0;
  if (rank_ == 0 && keep_steps >= 0) existing = std::filesystem::exists(h5_path());
  MPI_Bcast(&existing, 1, MPI_INT, 0, comm_);
  if (existing)
    continue_file(keep_steps);
  else
    create_file(mesh);
  write_xdmf_on_rank0();
}

void XdmfWriter::create_file(const OutputMesh& mesh) {
  const std::string h5 = h5_path();
  std::string error;
  {
    Hdf5Handle access(mpio_file_access(comm_), H5Pclose);
    if (!access.valid()) {
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
  const std::vector<int> own_rank(static_cast<std::size_t>(num_elements_), rank_);
  const int* owner = mesh.element_rank != nullptr ? mesh.element_rank : own_rank.data();
  throw_if_failed_anywhere(comm_, write_rows(file_.get(), "/mesh/coordinates", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE,
                                             nodes, mesh.owned_coordinates, h5));
  throw_if_failed_anywhere(comm_, write_rows(file_.get(), "/mesh/topology", H5T_STD_I64LE, H5T_NATIVE_INT64, hex,
                                             mesh.element_nodes, h5));
  throw_if_failed_anywhere(comm_, write_rows(file_.get(), "/mesh/rank", H5T_STD_I32LE, H5T_NATIVE_INT, cells,
                                             owner, h5));
  throw_if_failed_anywhere(comm_, write_rows(file_.get(), "/mesh/body", H5T_STD_I32LE, H5T_NATIVE_INT, cells,
                                             mesh.element_body, h5));
  if (!mesh.selections.empty()) {
    Hdf5Handle g(H5Gcreate2(file_.get(), "/mesh/sets", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose);
    if (!g.valid()) error = hdf5_failure("cannot create group /mesh/sets", h5);
    throw_if_failed_anywhere(comm_, error);
  }
  for (const OutputMesh::Selection& set : mesh.selections) {
    const auto block = RowBlock{hsize_t(set.size), 0, hsize_t(set.offset), hsize_t(set.count)};
    throw_if_failed_anywhere(comm_, write_rows(file_.get(), "/mesh/sets/" + set.name, H5T_STD_I64LE, H5T_NATIVE_INT64,
                                               block, set.ids, h5));
  }
  if (H5Fflush(file_.get(), H5F_SCOPE_GLOBAL) < 0) error = hdf5_failure("cannot flush", h5);
  throw_if_failed_anywhere(comm_, error);
}

// A restarted run's output: the steps before the checkpoint stay, later ones (written after
// the checkpoint by the run that was stopped) are unlinked, and writing goes on from there.
// The mesh must have the node and element counts of this run; its rows are in the input
// numbering (the driver's choice), so any rank count may continue any file.
void XdmfWriter::continue_file(std::int64_t keep_steps) {
  const std::string h5 = h5_path();
  std::string error;
  {
    Hdf5Handle access(mpio_file_access(comm_), H5Pclose);
    if (!access.valid()) {
      error = hdf5_failure("cannot set up MPI-IO file access", h5);
    } else {
      file_ = Hdf5Handle(H5Fopen(h5.c_str(), H5F_ACC_RDWR, access.get()), H5Fclose);
      if (!file_.valid()) error = "cannot open the output '" + h5 + "' to continue it: " + hdf5_error_text();
    }
  }
  throw_if_failed_anywhere(comm_, error);
  for (const auto& [path, rows] : {std::pair<const char*, std::int64_t>{"/mesh/coordinates", num_global_nodes_},
                                   {"/mesh/body", num_global_elements_}}) {
    Hdf5Handle dataset(H5Dopen2(file_.get(), path, H5P_DEFAULT), H5Dclose);
    Hdf5Handle space(dataset.valid() ? H5Dget_space(dataset.get()) : H5I_INVALID_HID, H5Sclose);
    hsize_t dims[2] = {0, 0};
    if (!space.valid() || H5Sget_simple_extent_dims(space.get(), dims, nullptr) < 0 ||
        dims[0] != static_cast<hsize_t>(rows)) {
      error = "the output '" + h5 + "' to continue has " + std::to_string(dims[0]) + " rows in " + path + ", this run " +
              std::to_string(rows) + " (another mesh)";
      break;
    }
  }
  throw_if_failed_anywhere(comm_, error);
  // The kept steps' times, then the later steps unlinked (all ranks alike: metadata is collective).
  hsize_t existing = 0;
  {
    Hdf5Handle steps(H5Gopen2(file_.get(), "/steps", H5P_DEFAULT), H5Gclose);
    H5G_info_t info;
    if (!steps.valid() || H5Gget_info(steps.get(), &info) < 0)
      error = hdf5_failure("cannot read group /steps", h5);
    else
      existing = info.nlinks;
  }
  throw_if_failed_anywhere(comm_, error);
  if (static_cast<std::int64_t>(existing) < keep_steps)
    error = "the output '" + h5 + "' holds " + std::to_string(existing) + " steps, the checkpoint was written after " +
            std::to_string(keep_steps);
  throw_if_failed_anywhere(comm_, error);
  step_times_.clear();
  for (std::int64_t k = 0; k < keep_steps && error.empty(); ++k) {
    const std::string step = "/steps/" + std::to_string(k);
    double time = 0;
    Hdf5Handle attribute(H5Aopen_by_name(file_.get(), step.c_str(), "time", H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
    if (!attribute.valid() || H5Aread(attribute.get(), H5T_NATIVE_DOUBLE, &time) < 0)
      error = hdf5_failure("cannot read " + step + "/time", h5);
    step_times_.push_back(time);
  }
  for (hsize_t k = static_cast<hsize_t>(keep_steps); k < existing && error.empty(); ++k) {
    const std::string step = "/steps/" + std::to_string(k);
    if (H5Lexists(file_.get(), step.c_str(), H5P_DEFAULT) > 0 && H5Ldelete(file_.get(), step.c_str(), H5P_DEFAULT) < 0)
      error = hdf5_failure("cannot remove " + step, h5);
  }
  if (error.empty() && H5Fflush(file_.get(), H5F_SCOPE_GLOBAL) < 0) error = hdf5_failure("cannot flush", h5);
  throw_if_failed_anywhere(comm_, error);
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
