// XdmfWriter: collective XDMF + HDF5 output (see xdmf_writer.hpp). Every stage ends with a
// collective error check so that all ranks throw together, and HDF5's own error printing is
// silenced while the writer works: its message goes into the exception instead.
#include "io/xdmf_writer.hpp"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <limits>
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
    return prefix + "offset " + std::to_string(offset) + " on rank " + std::to_string(rank) + " should be " +
           std::to_string(expected_offset) + " (blocks must follow rank order)";
  }
  return {};
}

// A fixed-length string type as wide as the longest of `texts` (null-terminated, ASCII/UTF-8).
Hdf5Handle string_type(const std::vector<std::string>& texts) {
  std::size_t width = 1;
  for (const std::string& t : texts) width = std::max(width, t.size() + 1);
  Hdf5Handle type(H5Tcopy(H5T_C_S1), H5Tclose);
  if (type.valid() && (H5Tset_size(type.get(), width) < 0 || H5Tset_strpad(type.get(), H5T_STR_NULLTERM) < 0 ||
                       H5Tset_cset(type.get(), H5T_CSET_UTF8) < 0))
    type.reset();
  return type;
}

// A scalar string attribute (collective: every rank passes the same text).
std::string write_string_attribute(hid_t object, const char* name, const std::string& text, const std::string& h5) {
  Hdf5Handle type = string_type({text});
  Hdf5Handle scalar(H5Screate(H5S_SCALAR), H5Sclose);
  std::vector<char> buffer(text.begin(), text.end());
  buffer.resize(text.size() + 1, '\0');
  Hdf5Handle attribute(type.valid() && scalar.valid()
                           ? H5Acreate2(object, name, type.get(), scalar.get(), H5P_DEFAULT, H5P_DEFAULT)
                           : H5I_INVALID_HID,
                       H5Aclose);
  if (!attribute.valid() || H5Awrite(attribute.get(), type.get(), buffer.data()) < 0)
    return hdf5_failure(std::string("cannot write attribute ") + name, h5);
  return {};
}

template <class T>
std::string write_scalar_attribute(hid_t object, const std::string& name, hid_t file_type, hid_t memory_type,
                                   const T& value, const std::string& h5) {
  Hdf5Handle scalar(H5Screate(H5S_SCALAR), H5Sclose);
  Hdf5Handle attribute(H5Acreate2(object, name.c_str(), file_type, scalar.get(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
  if (!attribute.valid() || H5Awrite(attribute.get(), memory_type, &value) < 0)
    return hdf5_failure("cannot write attribute " + name, h5);
  return {};
}

// Rows that every rank holds alike: rank 0 writes them all, the others take part with none.
RowBlock rank0_rows(MPI_Comm comm, hsize_t rows, hsize_t columns) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  return RowBlock{rows, columns, 0, rank == 0 ? rows : 0};
}

// The bodies' grids of a scene with kinematic bodies: each kinematic body its own grid named
// by the body, the other bodies in runs of consecutive rows (a run of one body named by it, a
// longer one "<first>..<last>"). dipc's driver numbers elements body by body in scene order,
// so each body is one run of rows; for a numbering that interleaves bodies the mesh stays one
// grid (the "kinematic" cell field still marks them). Collective; the same on every rank.
std::vector<XdmfCellRange> kinematic_body_grids(MPI_Comm comm, const OutputMesh& mesh,
                                                const std::vector<std::string>& names) {
  int local_bodies = 0;
  for (int e = 0; e < mesh.num_elements; ++e) local_bodies = std::max(local_bodies, mesh.element_body[e] + 1);
  int num_bodies = std::max<int>(local_bodies, static_cast<int>(names.size()));
  MPI_Allreduce(MPI_IN_PLACE, &num_bodies, 1, MPI_INT, MPI_MAX, comm);
  const std::int64_t none = std::numeric_limits<std::int64_t>::max();
  std::vector<std::int64_t> first(num_bodies, none), last(num_bodies, -1), count(num_bodies, 0);
  std::vector<int> kinematic(num_bodies, 0);
  for (int e = 0; e < mesh.num_elements; ++e) {
    const int b = mesh.element_body[e];
    const std::int64_t row = mesh.element_offset + e;
    first[b] = std::min(first[b], row);
    last[b] = std::max(last[b], row);
    ++count[b];
    kinematic[b] = std::max(kinematic[b], mesh.element_kinematic[e]);
  }
  MPI_Allreduce(MPI_IN_PLACE, first.data(), num_bodies, MPI_INT64_T, MPI_MIN, comm);
  MPI_Allreduce(MPI_IN_PLACE, last.data(), num_bodies, MPI_INT64_T, MPI_MAX, comm);
  MPI_Allreduce(MPI_IN_PLACE, count.data(), num_bodies, MPI_INT64_T, MPI_SUM, comm);
  MPI_Allreduce(MPI_IN_PLACE, kinematic.data(), num_bodies, MPI_INT, MPI_MAX, comm);

  std::vector<int> order;
  for (int b = 0; b < num_bodies; ++b)
    if (count[b] > 0) order.push_back(b);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return first[a] < first[b]; });
  std::int64_t next_row = 0;
  for (const int b : order) {
    if (first[b] != next_row || last[b] - first[b] + 1 != count[b]) return {};
    next_row += count[b];
  }
  const auto name = [&](int b) { return b < static_cast<int>(names.size()) ? names[b] : "body " + std::to_string(b); };
  std::vector<XdmfCellRange> grids;
  bool extend = false;  // the last grid is a run of non-kinematic bodies
  std::string run_first;
  for (const int b : order) {
    if (kinematic[b] || !extend) {
      grids.push_back({name(b), first[b], count[b]});
      extend = !kinematic[b];
      run_first = name(b);
      continue;
    }
    grids.back().count += count[b];
    grids.back().name = run_first + ".." + name(b);
  }
  return grids;
}

}  // namespace

std::string XdmfWriter::write_strings(hid_t parent, const std::string& path, const std::vector<std::string>& texts,
                                      const std::string& h5) const {
  Hdf5Handle type = string_type(texts);
  if (!type.valid()) return hdf5_failure("cannot make a string type for " + path, h5);
  const std::size_t width = H5Tget_size(type.get());
  std::vector<char> buffer(std::max<std::size_t>(1, texts.size()) * width, '\0');
  for (std::size_t i = 0; i < texts.size(); ++i)
    std::copy(texts[i].begin(), texts[i].end(), buffer.begin() + i * width);
  return write_rows(parent, path, type.get(), type.get(), rank0_rows(comm_, texts.size(), 0), buffer.data(), h5);
}

// /obstacles/<j>: name and kind attributes, rest coordinates, cells, and zero displacements for
// an obstacle that does not move (so that one "Warp By Vector" moves every block alike).
std::string XdmfWriter::write_obstacle(std::size_t j) const {
  const OutputObstacle& o = obstacles_[j];
  const std::string h5 = h5_path(), path = "/obstacles/" + std::to_string(j);
  Hdf5Handle group(H5Gcreate2(file_.get(), path.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose);
  if (!group.valid()) return hdf5_failure("cannot create group " + path, h5);
  std::string error = write_string_attribute(group.get(), "name", o.name, h5);
  if (error.empty()) error = write_string_attribute(group.get(), "kind", o.kind, h5);
  const hsize_t vertices = o.rest.size() / 3, cells = o.cells.size() / o.nodes_per_cell;
  if (error.empty())
    error = write_rows(group.get(), "coordinates", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, rank0_rows(comm_, vertices, 3),
                       o.rest.data(), h5);
  if (error.empty())
    error = write_rows(group.get(), "topology", H5T_STD_I64LE, H5T_NATIVE_INT64,
                       rank0_rows(comm_, cells, o.nodes_per_cell), o.cells.data(), h5);
  if (error.empty() && !o.moving) {
    const std::vector<double> zero(o.rest.size(), 0.0);
    error = write_rows(group.get(), "displacement", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, rank0_rows(comm_, vertices, 3),
                       zero.data(), h5);
  }
  return error;
}

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
      num_elements_(mesh.num_elements),
      contact_force_(mesh.contact_force),
      friction_force_(mesh.friction_force),
      body_names_(mesh.body_names),
      contact_pair_kinds_(mesh.contact_pair_kinds),
      obstacles_(mesh.obstacles) {
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
  for (const OutputObstacle& o : obstacles_)
    if (error.empty() && (o.nodes_per_cell < 3 || o.nodes_per_cell > 4 || o.rest.size() % 3 != 0 ||
                          o.cells.size() % o.nodes_per_cell != 0 || o.cells.empty()))
      error = "XdmfWriter: obstacle \"" + o.name + "\" has no cells or inconsistent array sizes";
  // Kinematic flags on any rank make /mesh/kinematic; every rank with elements must give them.
  int kinematic = mesh.element_kinematic != nullptr;
  MPI_Allreduce(MPI_IN_PLACE, &kinematic, 1, MPI_INT, MPI_MAX, comm_);
  kinematic_ = kinematic != 0;
  if (error.empty() && kinematic_ && num_elements_ > 0 && mesh.element_kinematic == nullptr)
    error = missing_array("element_kinematic", num_elements_);
  throw_if_failed_anywhere(comm_, error);
  if (kinematic_) body_grids_ = kinematic_body_grids(comm_, mesh, body_names_);

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

// Per-grid rows of cell fields (body_grids_): <parent>/grids/<g>/<name> holds rows [first,
// first + count) of the field, each rank writing the part of its element block inside them.
// Collective; throws on every rank on failure.
void XdmfWriter::write_grid_cells(hid_t parent, const std::string& parent_path,
                                  const std::vector<CellField>& fields) const {
  const std::string h5 = h5_path();
  Hdf5Handle grids(H5Gcreate2(parent, "grids", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose);
  throw_if_failed_anywhere(comm_,
                           grids.valid() ? "" : hdf5_failure("cannot create group " + parent_path + "/grids", h5));
  for (std::size_t g = 0; g < body_grids_.size(); ++g) {
    const XdmfCellRange& cells = body_grids_[g];
    const std::string name = std::to_string(g);
    Hdf5Handle group(H5Gcreate2(grids.get(), name.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose);
    throw_if_failed_anywhere(comm_, group.valid()
                                        ? ""
                                        : hdf5_failure("cannot create group " + parent_path + "/grids/" + name, h5));
    const std::int64_t begin = std::max(cells.first, element_offset_);
    const std::int64_t end = std::min(cells.first + cells.count, element_offset_ + num_elements_);
    const std::int64_t rows = std::max<std::int64_t>(0, end - begin);
    const auto block = RowBlock{hsize_t(cells.count), 0, hsize_t(rows > 0 ? begin - cells.first : 0), hsize_t(rows)};
    for (const CellField& f : fields) {
      const char* first_row = static_cast<const char*>(f.data) + (rows > 0 ? (begin - element_offset_) * f.bytes : 0);
      throw_if_failed_anywhere(comm_,
                               write_rows(group.get(), f.name, f.file_type, f.memory_type, block, first_row, h5));
    }
  }
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

  for (const char* group : {"/mesh", "/steps", "/obstacles"}) {
    Hdf5Handle g(H5Gcreate2(file_.get(), group, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose);
    if (!g.valid() && error.empty()) error = hdf5_failure(std::string("cannot create group ") + group, h5);
  }
  throw_if_failed_anywhere(comm_, error);

  const auto nodes = RowBlock{hsize_t(num_global_nodes_), 3, hsize_t(node_offset_), hsize_t(num_owned_nodes_)};
  const auto hex = RowBlock{hsize_t(num_global_elements_), 8, hsize_t(element_offset_), hsize_t(num_elements_)};
  const auto cells = RowBlock{hsize_t(num_global_elements_), 0, hsize_t(element_offset_), hsize_t(num_elements_)};
  const std::vector<int> own_rank(static_cast<std::size_t>(num_elements_), rank_);
  const int* owner = mesh.element_rank != nullptr ? mesh.element_rank : own_rank.data();
  throw_if_failed_anywhere(comm_, write_rows(file_.get(), "/mesh/coordinates", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, nodes,
                                             mesh.owned_coordinates, h5));
  throw_if_failed_anywhere(comm_, write_rows(file_.get(), "/mesh/topology", H5T_STD_I64LE, H5T_NATIVE_INT64, hex,
                                             mesh.element_nodes, h5));
  throw_if_failed_anywhere(comm_,
                           write_rows(file_.get(), "/mesh/rank", H5T_STD_I32LE, H5T_NATIVE_INT, cells, owner, h5));
  throw_if_failed_anywhere(comm_, write_rows(file_.get(), "/mesh/body", H5T_STD_I32LE, H5T_NATIVE_INT, cells,
                                             mesh.element_body, h5));
  if (kinematic_)
    throw_if_failed_anywhere(comm_, write_rows(file_.get(), "/mesh/kinematic", H5T_STD_I32LE, H5T_NATIVE_INT, cells,
                                               mesh.element_kinematic, h5));
  if (!body_names_.empty())
    throw_if_failed_anywhere(comm_, write_strings(file_.get(), "/mesh/body_names", body_names_, h5));
  if (!body_grids_.empty()) {
    Hdf5Handle group(H5Gopen2(file_.get(), "/mesh", H5P_DEFAULT), H5Gclose);
    write_grid_cells(group.get(), "/mesh",
                     {{"rank", H5T_STD_I32LE, H5T_NATIVE_INT, owner, sizeof(int)},
                      {"body", H5T_STD_I32LE, H5T_NATIVE_INT, mesh.element_body, sizeof(int)},
                      {"kinematic", H5T_STD_I32LE, H5T_NATIVE_INT, mesh.element_kinematic, sizeof(int)}});
  }
  for (std::size_t j = 0; j < obstacles_.size(); ++j) throw_if_failed_anywhere(comm_, write_obstacle(j));
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
      error = "the output '" + h5 + "' to continue has " + std::to_string(dims[0]) + " rows in " + path +
              ", this run " + std::to_string(rows) + " (another mesh)";
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

std::string XdmfWriter::xdmf_path() const { return (std::filesystem::path(directory_) / (name_ + ".xmf")).string(); }

void XdmfWriter::write_step(const StepFields& f) {
  const QuietHdf5Errors quiet;
  const std::string h5 = h5_path();
  std::string error;
  std::size_t moving = 0;
  for (const OutputObstacle& o : obstacles_) moving += o.moving ? 1 : 0;
  if (num_owned_nodes_ > 0 && (f.displacement == nullptr || f.velocity == nullptr)) {
    error = missing_array("displacement or velocity", num_owned_nodes_);
  } else if (num_owned_nodes_ > 0 &&
             ((contact_force_ && f.contact_force == nullptr) || (friction_force_ && f.friction_force == nullptr))) {
    error = missing_array("contact_force or friction_force", num_owned_nodes_);
  } else if (num_elements_ > 0 && f.volume_ratio == nullptr) {
    error = missing_array("volume_ratio", num_elements_);
  } else if (f.contact_pairs.size() != contact_pair_kinds_.size()) {
    error = "XdmfWriter: " + std::to_string(f.contact_pairs.size()) + " contact pair counts for " +
            std::to_string(contact_pair_kinds_.size()) + " kinds";
  } else if (f.obstacle_displacement.size() != moving) {
    error = "XdmfWriter: " + std::to_string(f.obstacle_displacement.size()) + " obstacle displacements for " +
            std::to_string(moving) + " moving obstacles";
  }
  for (std::size_t j = 0, m = 0; j < obstacles_.size() && error.empty(); ++j)
    if (obstacles_[j].moving && f.obstacle_displacement[m++].size() != obstacles_[j].rest.size())
      error = "XdmfWriter: the displacement of obstacle \"" + obstacles_[j].name + "\" has the wrong size";
  const double time = f.time;
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
    error = write_scalar_attribute(group.get(), "time", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, time, h5);
    for (std::size_t k = 0; k < contact_pair_kinds_.size() && error.empty(); ++k)
      error = write_scalar_attribute(group.get(), "contact_pairs_" + contact_pair_kinds_[k], H5T_STD_I64LE,
                                     H5T_NATIVE_LLONG, f.contact_pairs[k], h5);
  }
  throw_if_failed_anywhere(comm_, error);

  const auto nodes = RowBlock{hsize_t(num_global_nodes_), 3, hsize_t(node_offset_), hsize_t(num_owned_nodes_)};
  const auto cells = RowBlock{hsize_t(num_global_elements_), 0, hsize_t(element_offset_), hsize_t(num_elements_)};
  const auto node_field = [&](const char* name, const double* data) {
    throw_if_failed_anywhere(comm_, write_rows(group.get(), name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, nodes, data, h5));
  };
  node_field("displacement", f.displacement);
  node_field("velocity", f.velocity);
  if (contact_force_) node_field("contact_force", f.contact_force);
  if (friction_force_) node_field("friction_force", f.friction_force);
  throw_if_failed_anywhere(comm_, write_rows(group.get(), "volume_ratio", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, cells,
                                             f.volume_ratio, h5));
  if (!body_grids_.empty())
    write_grid_cells(group.get(), step,
                     {{"volume_ratio", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, f.volume_ratio, sizeof(double)}});
  if (moving > 0) {
    Hdf5Handle obstacles(H5Gcreate2(group.get(), "obstacles", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose);
    if (!obstacles.valid()) error = hdf5_failure("cannot create group " + step + "/obstacles", h5);
    throw_if_failed_anywhere(comm_, error);
    for (std::size_t j = 0, m = 0; j < obstacles_.size(); ++j) {
      if (!obstacles_[j].moving) continue;
      const std::string path = std::to_string(j) + "/displacement";
      Hdf5Handle g(H5Gcreate2(obstacles.get(), std::to_string(j).c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                   H5Gclose);
      if (!g.valid()) error = hdf5_failure("cannot create group " + step + "/obstacles/" + std::to_string(j), h5);
      throw_if_failed_anywhere(comm_, error);
      const std::vector<double>& u = f.obstacle_displacement[m++];
      throw_if_failed_anywhere(comm_, write_rows(g.get(), "displacement", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE,
                                                 rank0_rows(comm_, u.size() / 3, 3), u.data(), h5));
    }
  }
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
    XdmfLayout layout;
    layout.h5_file_name = name_ + ".h5";
    layout.num_nodes = num_global_nodes_;
    layout.num_elements = num_global_elements_;
    layout.kinematic = kinematic_;
    layout.contact_force = contact_force_;
    layout.friction_force = friction_force_;
    layout.body_names = body_names_;
    layout.body_grids = body_grids_;
    for (const OutputObstacle& o : obstacles_)
      layout.obstacles.push_back({o.name, o.nodes_per_cell, static_cast<std::int64_t>(o.rest.size() / 3),
                                  static_cast<std::int64_t>(o.cells.size() / o.nodes_per_cell), o.moving});
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
