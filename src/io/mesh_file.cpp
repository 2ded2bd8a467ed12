// MeshFileReader and write_mesh_file (see mesh_file.hpp).
#include "io/mesh_file.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "io/collective_error.hpp"
#include "io/hdf5_rows.hpp"

namespace dipc {
namespace {

// Dimensions of a dataset, or an error message.
std::string dataset_dims(hid_t file, const std::string& name, const std::string& path, int rank, hsize_t* dims) {
  if (H5Lexists(file, name.c_str(), H5P_DEFAULT) <= 0) return "'" + path + "' has no dataset " + name;
  Hdf5Handle dataset(H5Dopen2(file, name.c_str(), H5P_DEFAULT), H5Dclose);
  if (!dataset.valid()) return hdf5_failure("cannot open dataset " + name, path);
  Hdf5Handle space(H5Dget_space(dataset.get()), H5Sclose);
  if (!space.valid() || H5Sget_simple_extent_ndims(space.get()) != rank)
    return "dataset " + name + " in '" + path + "' must have " + std::to_string(rank) + " dimension(s)";
  H5Sget_simple_extent_dims(space.get(), dims, nullptr);
  return {};
}

// The first non-finite value of the rows `x` (3 per node, from row `begin`), named by its row
// and axis. Checked here, as read: the body's placement mixes the axes (0 · NaN is NaN), so a
// later check would blame the x coordinate for a NaN in y or z.
std::string non_finite_coordinate(const std::vector<double>& x, std::int64_t begin, const std::string& path) {
  for (std::size_t i = 0; i < x.size(); ++i)
    if (!std::isfinite(x[i]))
      return path + ": node " + std::to_string(begin + static_cast<std::int64_t>(i / 3)) + " has a non-finite " +
             "xyz"[i % 3] + " coordinate";
  return {};
}

}  // namespace

bool is_hdf5_mesh_path(const std::string& path) {
  auto ends_with = [&](const std::string& suffix) {
    if (path.size() < suffix.size()) return false;
    std::string tail = path.substr(path.size() - suffix.size());
    std::transform(tail.begin(), tail.end(), tail.begin(), [](unsigned char c) { return std::tolower(c); });
    return tail == suffix;
  };
  return ends_with(".h5") || ends_with(".hdf5");
}

MeshFileReader::MeshFileReader(MPI_Comm comm, const std::string& path) : comm_(comm), path_(path) {
  QuietHdf5Errors quiet;
  std::string error;
  {
    Hdf5Handle access(mpio_file_access(comm), H5Pclose);
    if (!access.valid())
      error = hdf5_failure("cannot set up MPI-IO access", path);
    else
      file_ = Hdf5Handle(H5Fopen(path.c_str(), H5F_ACC_RDONLY, access.get()), H5Fclose);
    if (error.empty() && !file_.valid()) error = hdf5_failure("cannot open the mesh file", path);
  }
  hsize_t coordinates[2] = {0, 0}, topology[2] = {0, 0};
  if (error.empty()) error = dataset_dims(file_.get(), "/mesh/coordinates", path, 2, coordinates);
  if (error.empty()) error = dataset_dims(file_.get(), "/mesh/topology", path, 2, topology);
  if (error.empty() && coordinates[1] != 3)
    error = "dataset /mesh/coordinates in '" + path + "' has " + std::to_string(coordinates[1]) +
            " columns, expected 3";
  if (error.empty() && topology[1] != 8)
    error = "dataset /mesh/topology in '" + path + "' has " + std::to_string(topology[1]) +
            " columns, expected 8 (hexahedra)";
  if (error.empty() && H5Lexists(file_.get(), "/mesh/sets", H5P_DEFAULT) > 0) {
    Hdf5Handle group(H5Gopen2(file_.get(), "/mesh/sets", H5P_DEFAULT), H5Gclose);
    H5G_info_t info;
    if (!group.valid() || H5Gget_info(group.get(), &info) < 0)
      error = hdf5_failure("cannot open group /mesh/sets", path);
    for (hsize_t i = 0; error.empty() && i < info.nlinks; ++i) {
      const ssize_t length = H5Lget_name_by_idx(group.get(), ".", H5_INDEX_NAME, H5_ITER_INC, i, nullptr, 0,
                                                H5P_DEFAULT);
      std::string name(static_cast<std::size_t>(std::max<ssize_t>(length, 0)) + 1, '\0');
      H5Lget_name_by_idx(group.get(), ".", H5_INDEX_NAME, H5_ITER_INC, i, name.data(), name.size(), H5P_DEFAULT);
      name.resize(static_cast<std::size_t>(std::max<ssize_t>(length, 0)));
      hsize_t size[1] = {0};
      error = dataset_dims(file_.get(), "/mesh/sets/" + name, path, 1, size);
      set_names_.push_back(name);
      set_sizes_.push_back(static_cast<std::int64_t>(size[0]));
    }
  }
  throw_if_failed_anywhere(comm, error);
  num_nodes_ = static_cast<std::int64_t>(coordinates[0]);
  num_elements_ = static_cast<std::int64_t>(topology[0]);
}

std::vector<double> MeshFileReader::read_coordinates(std::int64_t begin, std::int64_t count) const {
  QuietHdf5Errors quiet;
  std::vector<double> x(3 * static_cast<std::size_t>(count));
  const RowBlock block{hsize_t(num_nodes_), 3, hsize_t(begin), hsize_t(count)};
  throw_if_failed_anywhere(comm_,
                           read_rows(file_.get(), "/mesh/coordinates", H5T_NATIVE_DOUBLE, block, x.data(), path_));
  throw_if_failed_anywhere(comm_, non_finite_coordinate(x, begin, path_));
  return x;
}

std::vector<std::int64_t> MeshFileReader::read_topology(std::int64_t begin, std::int64_t count) const {
  QuietHdf5Errors quiet;
  std::vector<std::int64_t> t(8 * static_cast<std::size_t>(count));
  const RowBlock block{hsize_t(num_elements_), 8, hsize_t(begin), hsize_t(count)};
  throw_if_failed_anywhere(comm_, read_rows(file_.get(), "/mesh/topology", H5T_NATIVE_INT64, block, t.data(), path_));
  return t;
}

std::vector<std::int64_t> MeshFileReader::read_set(std::size_t set, std::int64_t begin, std::int64_t count) const {
  QuietHdf5Errors quiet;
  std::vector<std::int64_t> ids(static_cast<std::size_t>(count));
  const RowBlock block{hsize_t(set_sizes_[set]), 0, hsize_t(begin), hsize_t(count)};
  throw_if_failed_anywhere(comm_, read_rows(file_.get(), "/mesh/sets/" + set_names_[set], H5T_NATIVE_INT64, block,
                                            ids.data(), path_));
  return ids;
}

void write_mesh_file(MPI_Comm comm, const std::string& path, const MeshFileRows& rows) {
  QuietHdf5Errors quiet;
  std::string error;
  for (const auto& set : rows.sets)
    if (set.name.empty() || set.name.find('/') != std::string::npos)
      error = "selection name \"" + set.name + "\" cannot be an HDF5 dataset name (empty or with '/')";
  throw_if_failed_anywhere(comm, error);
  Hdf5Handle file;
  {
    Hdf5Handle access(mpio_file_access(comm), H5Pclose);
    if (access.valid()) file = Hdf5Handle(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, access.get()), H5Fclose);
    if (!file.valid()) error = hdf5_failure("cannot create the mesh file", path);
  }
  throw_if_failed_anywhere(comm, error);
  for (const char* group : {"/mesh", "/mesh/sets"}) {
    Hdf5Handle g(H5Gcreate2(file.get(), group, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose);
    if (!g.valid()) error = hdf5_failure(std::string("cannot create group ") + group, path);
    throw_if_failed_anywhere(comm, error);
  }
  const RowBlock nodes{hsize_t(rows.num_nodes), 3, hsize_t(rows.node_offset), hsize_t(rows.node_count)};
  const RowBlock hexes{hsize_t(rows.num_elements), 8, hsize_t(rows.element_offset), hsize_t(rows.element_count)};
  const RowBlock cells{hsize_t(rows.num_elements), 0, hsize_t(rows.element_offset), hsize_t(rows.element_count)};
  throw_if_failed_anywhere(comm, write_rows(file.get(), "/mesh/coordinates", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, nodes,
                                            rows.coordinates, path));
  throw_if_failed_anywhere(comm, write_rows(file.get(), "/mesh/topology", H5T_STD_I64LE, H5T_NATIVE_INT64, hexes,
                                            rows.topology, path));
  throw_if_failed_anywhere(comm, write_rows(file.get(), "/mesh/body", H5T_STD_I32LE, H5T_NATIVE_INT32, cells, rows.body,
                                            path));
  for (const auto& set : rows.sets) {
    const RowBlock block{hsize_t(set.size), 0, hsize_t(set.offset), hsize_t(set.count)};
    throw_if_failed_anywhere(comm, write_rows(file.get(), "/mesh/sets/" + set.name, H5T_STD_I64LE, H5T_NATIVE_INT64,
                                              block, set.ids, path));
  }
  if (!file.reset()) error = hdf5_failure("cannot close the mesh file", path);
  throw_if_failed_anywhere(comm, error);
}

}  // namespace dipc
