// CheckpointFile: collective HDF5 checkpoint (see checkpoint_file.hpp).
#include "io/checkpoint_file.hpp"

#include <cstring>
#include <filesystem>

#include "io/collective_error.hpp"
#include "io/hdf5_handle.hpp"
#include "io/hdf5_rows.hpp"

namespace dipc {
namespace {

constexpr const char* kFormat = "dipc checkpoint";

// splitmix64's finaliser (Steele, Lea, Flood 2014): a well-mixed 64-bit hash of one word.
std::uint64_t mix(std::uint64_t z) {
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

// This rank's part of a field's checksum: Σ mix(mix(index) ^ bits(value)) over its entries,
// index = 3·row + column in the whole field; summed over ranks (mod 2^64) it is independent of
// the split.
std::uint64_t partial_checksum(const std::vector<double>& values, std::int64_t node_offset) {
  std::uint64_t sum = 0;
  for (std::size_t i = 0; i < values.size(); ++i) {
    std::uint64_t bits;
    std::memcpy(&bits, &values[i], sizeof bits);
    sum += mix(mix(static_cast<std::uint64_t>(3 * node_offset) + i) ^ bits);
  }
  return sum;
}

std::uint64_t checksum(MPI_Comm comm, const std::vector<double>& values, std::int64_t node_offset) {
  std::uint64_t mine = partial_checksum(values, node_offset), total = 0;
  MPI_Allreduce(&mine, &total, 1, MPI_UINT64_T, MPI_SUM, comm);
  return total;
}

std::string write_attribute(hid_t object, const char* name, hid_t file_type, hid_t memory_type, const void* value,
                            const std::string& path) {
  Hdf5Handle scalar(H5Screate(H5S_SCALAR), H5Sclose);
  Hdf5Handle attribute(H5Acreate2(object, name, file_type, scalar.get(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
  if (!attribute.valid() || H5Awrite(attribute.get(), memory_type, value) < 0)
    return hdf5_failure(std::string("cannot write attribute ") + name, path);
  return {};
}

std::string write_text_attribute(hid_t object, const char* name, const std::string& text, const std::string& path) {
  Hdf5Handle type(H5Tcopy(H5T_C_S1), H5Tclose);
  H5Tset_size(type.get(), std::max<std::size_t>(1, text.size()));
  H5Tset_strpad(type.get(), H5T_STR_NULLPAD);
  return write_attribute(object, name, type.get(), type.get(), text.empty() ? "" : text.c_str(), path);
}

// Empty when `object` has no such attribute (the caller says what is missing).
bool read_attribute(hid_t object, const char* name, hid_t memory_type, void* value) {
  if (H5Aexists(object, name) <= 0) return false;
  Hdf5Handle attribute(H5Aopen(object, name, H5P_DEFAULT), H5Aclose);
  return attribute.valid() && H5Aread(attribute.get(), memory_type, value) >= 0;
}

bool read_text_attribute(hid_t object, const char* name, std::string* text) {
  if (H5Aexists(object, name) <= 0) return false;
  Hdf5Handle attribute(H5Aopen(object, name, H5P_DEFAULT), H5Aclose);
  Hdf5Handle type(attribute.valid() ? H5Aget_type(attribute.get()) : H5I_INVALID_HID, H5Tclose);
  if (!type.valid() || H5Tget_class(type.get()) != H5T_STRING || H5Tis_variable_str(type.get()) > 0) return false;
  std::vector<char> buffer(H5Tget_size(type.get()) + 1, '\0');
  if (H5Aread(attribute.get(), type.get(), buffer.data()) < 0) return false;
  *text = buffer.data();
  return true;
}

// A failure seen on any rank, with its kind, thrown as CheckpointError on every rank.
void throw_checkpoint_error_anywhere(MPI_Comm comm, CheckpointError::Kind kind, const std::string& error) {
  try {
    throw_if_failed_anywhere(comm, error.empty() ? error : std::to_string(static_cast<int>(kind)) + error);
  } catch (const std::runtime_error& e) {
    const std::string text = e.what();
    throw CheckpointError(static_cast<CheckpointError::Kind>(text[0] - '0'), text.substr(1));
  }
}

}  // namespace

void write_checkpoint_file(MPI_Comm comm, const std::string& path, const CheckpointContents& c) {
  const QuietHdf5Errors quiet;
  int rank;
  MPI_Comm_rank(comm, &rank);
  const std::string temporary = path + ".tmp";
  std::string error;
  {
    Hdf5Handle file;
    {
      Hdf5Handle access(mpio_file_access(comm), H5Pclose);
      if (access.valid())
        file = Hdf5Handle(H5Fcreate(temporary.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, access.get()), H5Fclose);
      if (!file.valid()) error = "cannot create checkpoint '" + temporary + "': " + hdf5_error_text();
    }
    throw_if_failed_anywhere(comm, error);
    // Attributes are metadata: every rank writes the same values (collective metadata writes).
    const std::int64_t version = kCheckpointVersion;
    error = write_text_attribute(file.get(), "format", kFormat, temporary);
    if (error.empty())
      error = write_attribute(file.get(), "version", H5T_STD_I64LE, H5T_NATIVE_INT64, &version, temporary);
    for (const auto& [name, value] : c.integers)
      if (error.empty())
        error = write_attribute(file.get(), name.c_str(), H5T_STD_I64LE, H5T_NATIVE_INT64, &value, temporary);
    for (const auto& [name, value] : c.reals)
      if (error.empty())
        error = write_attribute(file.get(), name.c_str(), H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, &value, temporary);
    for (const auto& [name, value] : c.texts)
      if (error.empty()) error = write_text_attribute(file.get(), name.c_str(), value, temporary);
    throw_if_failed_anywhere(comm, error);
    Hdf5Handle nodes(H5Gcreate2(file.get(), "/nodes", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose);
    if (!nodes.valid()) error = hdf5_failure("cannot create group /nodes", temporary);
    throw_if_failed_anywhere(comm, error);
    const RowBlock block{hsize_t(c.num_global_nodes), 3, hsize_t(c.node_offset), hsize_t(c.num_block_nodes)};
    for (const auto& [name, values] : c.node_fields) {
      if (values.size() != 3 * static_cast<std::size_t>(c.num_block_nodes))
        error = "checkpoint field " + name + " has " + std::to_string(values.size()) + " values for " +
                std::to_string(c.num_block_nodes) + " nodes";
      throw_if_failed_anywhere(comm, error);
      throw_if_failed_anywhere(comm, write_rows(nodes.get(), name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, block,
                                                values.data(), temporary));
      Hdf5Handle dataset(H5Dopen2(nodes.get(), name.c_str(), H5P_DEFAULT), H5Dclose);
      const std::uint64_t sum = checksum(comm, values, c.node_offset);
      error = dataset.valid()
                  ? write_attribute(dataset.get(), "checksum", H5T_STD_U64LE, H5T_NATIVE_UINT64, &sum, temporary)
                  : hdf5_failure("cannot open dataset " + name, temporary);
      throw_if_failed_anywhere(comm, error);
    }
    nodes.reset();
    if (!file.reset()) error = hdf5_failure("cannot close checkpoint", temporary);
    throw_if_failed_anywhere(comm, error);
  }
  // Complete and closed on every rank: only now may it take its final name.
  MPI_Barrier(comm);
  if (rank == 0) {
    std::error_code ec;
    std::filesystem::rename(temporary, path, ec);
    if (ec) error = "cannot rename '" + temporary + "' to '" + path + "': " + ec.message();
  }
  throw_if_failed_anywhere(comm, error);
}

void read_checkpoint_file(MPI_Comm comm, const std::string& path, CheckpointContents* c) {
  using Kind = CheckpointError::Kind;
  const QuietHdf5Errors quiet;
  int rank;
  MPI_Comm_rank(comm, &rank);
  const std::string named = "checkpoint '" + path + "'";
  // Rank 0 looks at the file before the ranks open it together.
  Kind kind = Kind::unreadable;
  std::string error;
  if (rank == 0) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) {
      error = named + " does not exist or is not a file";
    } else if (H5Fis_hdf5(path.c_str()) <= 0) {
      kind = Kind::foreign;
      error = named + " is not an HDF5 file, so not a dipc checkpoint";
    }
  }
  throw_checkpoint_error_anywhere(comm, kind, error);

  Hdf5Handle file;
  {
    Hdf5Handle access(mpio_file_access(comm), H5Pclose);
    if (access.valid()) file = Hdf5Handle(H5Fopen(path.c_str(), H5F_ACC_RDONLY, access.get()), H5Fclose);
    if (!file.valid()) {
      const std::string why = hdf5_error_text();
      kind = why.find("truncated") != std::string::npos ? Kind::truncated : Kind::corrupt;
      error = named + (kind == Kind::truncated ? " is truncated" : " is corrupt") + " (HDF5: " + why + ")";
    }
  }
  throw_checkpoint_error_anywhere(comm, kind, error);

  std::string format;
  std::int64_t version = 0;
  if (!read_text_attribute(file.get(), "format", &format) || format != kFormat) {
    kind = Kind::foreign;
    error = named + " is an HDF5 file but not a dipc checkpoint (no format = \"" + kFormat + "\" attribute)";
  } else if (!read_attribute(file.get(), "version", H5T_NATIVE_INT64, &version) || version != kCheckpointVersion) {
    kind = Kind::version;
    error = named + " has format version " + std::to_string(version) + "; this dipc reads version " +
            std::to_string(kCheckpointVersion);
  }
  throw_checkpoint_error_anywhere(comm, kind, error);

  kind = Kind::corrupt;
  for (auto& [name, value] : c->integers)
    if (error.empty() && !read_attribute(file.get(), name.c_str(), H5T_NATIVE_INT64, &value))
      error = named + " is corrupt: attribute " + name + " is missing or unreadable";
  for (auto& [name, value] : c->reals)
    if (error.empty() && !read_attribute(file.get(), name.c_str(), H5T_NATIVE_DOUBLE, &value))
      error = named + " is corrupt: attribute " + name + " is missing or unreadable";
  for (auto& [name, value] : c->texts)
    if (error.empty() && !read_text_attribute(file.get(), name.c_str(), &value))
      error = named + " is corrupt: attribute " + name + " is missing or unreadable";
  throw_checkpoint_error_anywhere(comm, kind, error);

  const RowBlock block{hsize_t(c->num_global_nodes), 3, hsize_t(c->node_offset), hsize_t(c->num_block_nodes)};
  for (auto& [name, values] : c->node_fields) {
    const std::string dataset_path = "/nodes/" + name;
    values.assign(3 * static_cast<std::size_t>(c->num_block_nodes), 0.0);
    // Rows first: another node count is another mesh, not damage.
    hsize_t dims[2] = {0, 0};
    {
      Hdf5Handle dataset(H5Dopen2(file.get(), dataset_path.c_str(), H5P_DEFAULT), H5Dclose);
      Hdf5Handle space(dataset.valid() ? H5Dget_space(dataset.get()) : H5I_INVALID_HID, H5Sclose);
      if (!space.valid() || H5Sget_simple_extent_dims(space.get(), dims, nullptr) < 0) {
        error = named + " is corrupt: dataset " + dataset_path + " is missing or unreadable";
      } else if (dims[0] != block.global_rows) {
        kind = Kind::mismatched;
        error = named + " holds " + std::to_string(dims[0]) + " nodes, this run's mesh " +
                std::to_string(block.global_rows) + " (another mesh)";
      }
    }
    throw_checkpoint_error_anywhere(comm, kind, error);
    error = read_rows(file.get(), dataset_path, H5T_NATIVE_DOUBLE, block, values.data(), path);
    if (!error.empty()) error = named + " is corrupt: " + error;
    throw_checkpoint_error_anywhere(comm, kind, error);
    std::uint64_t stored = 0;
    {
      Hdf5Handle dataset(H5Dopen2(file.get(), dataset_path.c_str(), H5P_DEFAULT), H5Dclose);
      if (!dataset.valid() || !read_attribute(dataset.get(), "checksum", H5T_NATIVE_UINT64, &stored))
        error = named + " is corrupt: " + dataset_path + " has no checksum";
    }
    throw_checkpoint_error_anywhere(comm, kind, error);
    if (checksum(comm, values, c->node_offset) != stored)
      error = named + " is corrupt: the data of " + dataset_path + " does not match its checksum";
    throw_checkpoint_error_anywhere(comm, kind, error);
  }
}

}  // namespace dipc
