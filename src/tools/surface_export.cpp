// read_step_surface, body_surface and export_surface (see surface_export.hpp). The output file
// is read serially (one process, HDF5's default driver): the tool runs beside a finished run,
// often where no MPI launcher is at hand. Whole datasets are read at once; at 20M hexes the
// topology is 1.3 GB and the face matching needs about as much again.
#include "tools/surface_export.hpp"

#include <hdf5.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <set>
#include <stdexcept>

#include "io/hdf5_handle.hpp"
#include "io/hdf5_rows.hpp"
#include "io/xdmf_text.hpp"
#include "mesh/boundary_faces.hpp"
#include "mesh/mesh_error.hpp"

namespace dipc {
namespace {

// The raw arrays below are written as they lie in memory, and the .vtp says LittleEndian.
static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "dipc-surface writes little-endian VTK files");
// Nodes and hexes are read straight into HexMesh's arrays, rows of 3 doubles and 8 int64.
static_assert(sizeof(Vec3) == 3 * sizeof(double) && sizeof(Hex) == 8 * sizeof(std::int64_t));
static_assert(sizeof(std::array<float, 3>) == 3 * sizeof(float));
static_assert(sizeof(std::array<std::int32_t, 4>) == 4 * sizeof(std::int32_t));

constexpr std::int64_t kMaxInt32 = std::numeric_limits<std::int32_t>::max();

class OutputFile {
 public:
  explicit OutputFile(const std::string& path) : path_(path) {
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) throw std::runtime_error("'" + path + "' does not exist");
    file_ = Hdf5Handle(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
    if (!file_.valid()) throw std::runtime_error("cannot open '" + path + "' as HDF5: " + hdf5_error_text());
  }

  hid_t get() const { return file_.get(); }
  const std::string& path() const { return path_; }
  bool exists(const std::string& name) const { return H5Lexists(file_.get(), name.c_str(), H5P_DEFAULT) > 0; }

  // The row count of dataset `name`, which must be rows x columns (columns == 0: one-dimensional).
  hsize_t rows(const std::string& name, hsize_t columns) const {
    if (!exists(name)) throw std::runtime_error("'" + path_ + "' has no dataset " + name);
    Hdf5Handle dataset = open(name);
    Hdf5Handle space(H5Dget_space(dataset.get()), H5Sclose);
    const int rank = columns == 0 ? 1 : 2;
    hsize_t dims[2] = {0, 0};
    const int found = space.valid() ? H5Sget_simple_extent_ndims(space.get()) : -1;
    if (found != rank || H5Sget_simple_extent_dims(space.get(), dims, nullptr) < 0 || (rank == 2 && dims[1] != columns))
      throw std::runtime_error("dataset " + name + " in '" + path_ + "' has " +
                               (found == 2 ? std::to_string(dims[0]) + " x " + std::to_string(dims[1]) + " entries"
                                           : std::to_string(found) + " dimension(s)") +
                               ", expected " + (rank == 1 ? "1 dimension" : "N x " + std::to_string(columns)));
    return dims[0];
  }

  // The whole dataset, converted by HDF5 to `memory_type`; `data` has room for all of it.
  void read(const std::string& name, hid_t memory_type, void* data) const {
    Hdf5Handle dataset = open(name);
    if (H5Dread(dataset.get(), memory_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0)
      throw std::runtime_error(hdf5_failure("cannot read dataset " + name, path_));
  }

  Hdf5Handle open(const std::string& name) const {
    Hdf5Handle dataset(H5Dopen2(file_.get(), name.c_str(), H5P_DEFAULT), H5Dclose);
    if (!dataset.valid()) throw std::runtime_error(hdf5_failure("cannot open dataset " + name, path_));
    return dataset;
  }

 private:
  std::string path_;
  Hdf5Handle file_;
};

// Step groups are named by their number; `wanted` < 0 asks for the highest.
std::int64_t find_step(const OutputFile& file, std::int64_t wanted) {
  Hdf5Handle steps(file.exists("/steps") ? H5Gopen2(file.get(), "/steps", H5P_DEFAULT) : H5I_INVALID_HID, H5Gclose);
  H5G_info_t info;
  if (!steps.valid() || H5Gget_info(steps.get(), &info) < 0)
    throw std::runtime_error("'" + file.path() + "' has no group /steps (not a dipc output file?)");
  std::int64_t last = -1;
  for (hsize_t i = 0; i < info.nlinks; ++i) {
    char name[32] = {};
    if (H5Lget_name_by_idx(steps.get(), ".", H5_INDEX_NAME, H5_ITER_INC, i, name, sizeof name, H5P_DEFAULT) < 0)
      throw std::runtime_error(hdf5_failure("cannot list /steps", file.path()));
    char* end = nullptr;
    const long long k = std::strtoll(name, &end, 10);
    if (*name != '\0' && *end == '\0' && k >= 0) last = std::max<std::int64_t>(last, k);
  }
  if (last < 0) throw std::runtime_error("'" + file.path() + "' has no written step (/steps is empty)");
  if (wanted < 0) return last;
  if (!file.exists("/steps/" + std::to_string(wanted)))
    throw std::runtime_error("'" + file.path() + "' has no step " + std::to_string(wanted) +
                             " (last written step: " + std::to_string(last) + ")");
  return wanted;
}

double step_time(const OutputFile& file, std::int64_t step) {
  const std::string group = "/steps/" + std::to_string(step);
  double time = 0;
  Hdf5Handle attribute(H5Aexists_by_name(file.get(), group.c_str(), "time", H5P_DEFAULT) > 0
                           ? H5Aopen_by_name(file.get(), group.c_str(), "time", H5P_DEFAULT, H5P_DEFAULT)
                           : H5I_INVALID_HID,
                       H5Aclose);
  if (!attribute.valid() || H5Aread(attribute.get(), H5T_NATIVE_DOUBLE, &time) < 0)
    throw std::runtime_error("cannot read attribute time of " + group + " in '" + file.path() + "'");
  return time;
}

// /mesh/body_names: fixed-length strings, as the writer stores them; none where it is absent.
std::vector<std::string> body_names(const OutputFile& file) {
  const std::string name = "/mesh/body_names";
  if (!file.exists(name)) return {};
  const hsize_t count = file.rows(name, 0);
  Hdf5Handle dataset = file.open(name);
  Hdf5Handle type(H5Dget_type(dataset.get()), H5Tclose);
  if (!type.valid() || H5Tget_class(type.get()) != H5T_STRING || H5Tis_variable_str(type.get()) != 0)
    throw std::runtime_error("dataset " + name + " in '" + file.path() + "' does not hold fixed-length strings");
  const std::size_t width = H5Tget_size(type.get());
  std::vector<char> buffer(count * width + 1, '\0');
  if (count > 0 && H5Dread(dataset.get(), type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, buffer.data()) < 0)
    throw std::runtime_error(hdf5_failure("cannot read dataset " + name, file.path()));
  std::vector<std::string> names;
  for (hsize_t i = 0; i < count; ++i) {
    const char* text = buffer.data() + i * width;
    names.emplace_back(text, strnlen(text, width));
  }
  return names;
}

std::int32_t checked_int32(std::int64_t value, const std::string& what) {
  if (value > kMaxInt32)
    throw std::runtime_error(what + " (" + std::to_string(value) + ") exceed the Int32 indices of the .vtp file");
  return static_cast<std::int32_t>(value);
}

// Appended raw data of a VTK XML file: each array is a UInt64 byte count followed by its bytes,
// at the offset the XML names, counted from the byte after the '_' that opens the data.
class AppendedData {
 public:
  std::uint64_t add(const void* data, std::uint64_t bytes) {
    blocks_.push_back({data, bytes});
    const std::uint64_t offset = size_;
    size_ += sizeof(std::uint64_t) + bytes;
    return offset;
  }
  std::uint64_t size() const { return size_; }
  void write(std::ostream& out) const {
    for (const Block& b : blocks_) {
      out.write(reinterpret_cast<const char*>(&b.bytes), sizeof b.bytes);
      out.write(static_cast<const char*>(b.data), static_cast<std::streamsize>(b.bytes));
    }
  }

 private:
  struct Block {
    const void* data;
    std::uint64_t bytes;
  };
  std::vector<Block> blocks_;
  std::uint64_t size_ = 0;
};

std::string cannot(const std::string& what, const std::string& path) {
  return "cannot " + what + " '" + path + "': " + std::strerror(errno);
}

// Writes `text` followed by `data` to `path`; returns the byte count.
std::uint64_t write_file(const std::string& path, const std::string& text, const AppendedData* data,
                         const std::string& tail) {
  errno = 0;
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) throw std::runtime_error(cannot("create", path));
  out << text;
  if (data != nullptr) data->write(out);
  out << tail;
  out.close();
  if (!out) throw std::runtime_error(cannot("write", path));
  return text.size() + (data != nullptr ? data->size() : 0) + tail.size();
}

std::uint64_t write_vtp(const std::string& path, const QuadSurface& s, double time) {
  const std::int32_t num_quads = checked_int32(static_cast<std::int64_t>(s.quads.size()), "the surface quads");
  checked_int32(4 * static_cast<std::int64_t>(s.quads.size()), "4 x the surface quads");
  std::vector<std::int32_t> offsets(s.quads.size());
  for (std::int32_t q = 0; q < num_quads; ++q) offsets[q] = 4 * (q + 1);

  AppendedData data;
  const std::uint64_t time_at = data.add(&time, sizeof time);
  const std::uint64_t body_at = data.add(s.body.data(), s.body.size() * sizeof(std::int32_t));
  const std::uint64_t points_at = data.add(s.points.data(), s.points.size() * sizeof(s.points[0]));
  const std::uint64_t connectivity_at = data.add(s.quads.data(), s.quads.size() * sizeof(s.quads[0]));
  const std::uint64_t offsets_at = data.add(offsets.data(), offsets.size() * sizeof(std::int32_t));
  const auto array = [](const char* type, const char* name, int components, std::uint64_t offset) {
    return std::string("        <DataArray type=\"") + type + "\"" +
           (*name ? std::string(" Name=\"") + name + "\"" : "") +
           (components > 1 ? " NumberOfComponents=\"" + std::to_string(components) + "\"" : "") +
           " format=\"appended\" offset=\"" + std::to_string(offset) + "\"/>\n";
  };
  // TimeValue is the field-data name VTK's readers and ParaView take for a data set's time.
  const std::string xml =
      "<?xml version=\"1.0\"?>\n"
      "<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
      "  <PolyData>\n"
      "    <FieldData>\n"
      "      <DataArray type=\"Float64\" Name=\"TimeValue\" NumberOfTuples=\"1\" format=\"appended\" offset=\"" +
      std::to_string(time_at) +
      "\"/>\n"
      "    </FieldData>\n"
      "    <Piece NumberOfPoints=\"" +
      std::to_string(s.points.size()) +
      "\" NumberOfVerts=\"0\" NumberOfLines=\"0\" NumberOfStrips=\"0\" NumberOfPolys=\"" +
      std::to_string(s.quads.size()) +
      "\">\n"
      "      <CellData Scalars=\"body\">\n" +
      array("Int32", "body", 1, body_at) +
      "      </CellData>\n"
      "      <Points>\n" +
      array("Float32", "", 3, points_at) +
      "      </Points>\n"
      "      <Polys>\n" +
      array("Int32", "connectivity", 1, connectivity_at) + array("Int32", "offsets", 1, offsets_at) +
      "      </Polys>\n"
      "    </Piece>\n"
      "  </PolyData>\n"
      "  <AppendedData encoding=\"raw\">\n"
      "   _";
  return write_file(path, xml, &data, "\n  </AppendedData>\n</VTKFile>\n");
}

struct Block {
  std::string name, file;  // file: relative to the .vtm's directory
};

std::uint64_t write_vtm(const std::string& path, const std::vector<Block>& blocks) {
  std::string xml =
      "<?xml version=\"1.0\"?>\n"
      "<VTKFile type=\"vtkMultiBlockDataSet\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
      "  <vtkMultiBlockDataSet>\n";
  for (std::size_t i = 0; i < blocks.size(); ++i)
    xml += "    <DataSet index=\"" + std::to_string(i) + "\" name=\"" + xml_escaped(blocks[i].name) + "\" file=\"" +
           xml_escaped(blocks[i].file) + "\"/>\n";
  xml += "  </vtkMultiBlockDataSet>\n</VTKFile>\n";
  return write_file(path, xml, nullptr, "");
}

// Files written under "<path>.tmp" and renamed to their paths together by commit(); whatever
// was not renamed is removed, so a failed export leaves nothing behind.
class PendingFiles {
 public:
  PendingFiles() = default;
  PendingFiles(const PendingFiles&) = delete;
  PendingFiles& operator=(const PendingFiles&) = delete;
  ~PendingFiles() {
    std::error_code ec;
    for (std::size_t i = renamed_; i < paths_.size(); ++i) std::filesystem::remove(paths_[i] + ".tmp", ec);
  }
  std::string add(const std::string& path) {
    paths_.push_back(path);
    return path + ".tmp";
  }
  void commit() {
    for (; renamed_ < paths_.size(); ++renamed_) {
      std::error_code ec;
      std::filesystem::rename(paths_[renamed_] + ".tmp", paths_[renamed_], ec);
      if (ec)
        throw std::runtime_error("cannot rename '" + paths_[renamed_] + ".tmp' to '" + paths_[renamed_] +
                                 "': " + ec.message());
    }
  }
  const std::vector<std::string>& paths() const { return paths_; }

 private:
  std::vector<std::string> paths_;
  std::size_t renamed_ = 0;
};

// A body name as part of a file name: characters other than letters, digits, '.', '-' and '_'
// become '_'.
std::string file_safe(const std::string& name) {
  std::string out = name;
  for (char& c : out)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '.' && c != '-' && c != '_') c = '_';
  return out;
}

}  // namespace

StepSurface read_step_surface(const std::string& h5_path, std::int64_t step) {
  QuietHdf5Errors quiet;
  const OutputFile file(h5_path);
  StepSurface result;
  result.step = find_step(file, step);
  result.time = step_time(file, result.step);
  result.body_names = body_names(file);

  // Every shape is checked before the big reads, so a malformed file fails at once.
  const std::string displacement = "/steps/" + std::to_string(result.step) + "/displacement";
  const hsize_t num_nodes = file.rows("/mesh/coordinates", 3);
  const hsize_t num_elements = file.rows("/mesh/topology", 8);
  if (file.rows("/mesh/body", 0) != num_elements)
    throw std::runtime_error("dataset /mesh/body in '" + h5_path + "' has " +
                             std::to_string(file.rows("/mesh/body", 0)) + " rows, /mesh/topology " +
                             std::to_string(num_elements));
  if (file.rows(displacement, 3) != num_nodes)
    throw std::runtime_error("dataset " + displacement + " in '" + h5_path + "' has " +
                             std::to_string(file.rows(displacement, 3)) + " rows, /mesh/coordinates " +
                             std::to_string(num_nodes));
  result.num_elements = static_cast<std::int64_t>(num_elements);

  HexMesh mesh;
  mesh.nodes.resize(num_nodes);
  mesh.hexes.resize(num_elements);
  mesh.body.resize(num_elements);
  file.read("/mesh/coordinates", H5T_NATIVE_DOUBLE, mesh.nodes.data());
  file.read("/mesh/topology", H5T_NATIVE_INT64, mesh.hexes.data());
  file.read("/mesh/body", H5T_NATIVE_INT, mesh.body.data());
  for (hsize_t e = 0; e < num_elements; ++e)
    if (mesh.body[e] < 0)
      throw std::runtime_error("dataset /mesh/body in '" + h5_path + "' has the negative body id " +
                               std::to_string(mesh.body[e]) + " in row " + std::to_string(e));
  std::vector<BoundaryFace> faces;
  try {
    faces = extract_boundary_faces(mesh);
  } catch (const MeshError& e) {
    throw std::runtime_error("dataset /mesh/topology in '" + h5_path + "': " + e.what());
  }

  // Points are the nodes the faces use, in ascending node id (which keeps the input's locality).
  std::vector<std::int32_t> point(num_nodes, -1);
  for (const BoundaryFace& f : faces)
    for (const int local : hex_face_nodes(f.face)) point[mesh.hexes[f.element][local]] = 0;
  std::int64_t num_points = 0;
  for (std::int32_t& p : point)
    if (p == 0) p = checked_int32(num_points++, "the surface nodes");
  QuadSurface& s = result.surface;
  s.quads.reserve(faces.size());
  s.body.reserve(faces.size());
  for (const BoundaryFace& f : faces) {
    const std::array<int, 4> local = hex_face_nodes(f.face);
    const Hex& hex = mesh.hexes[f.element];
    s.quads.push_back({point[hex[local[0]]], point[hex[local[1]]], point[hex[local[2]]], point[hex[local[3]]]});
    s.body.push_back(mesh.body[f.element]);
  }
  std::vector<Hex>().swap(mesh.hexes);  // not needed any more: room for the displacement

  std::vector<Vec3> u(num_nodes);
  file.read(displacement, H5T_NATIVE_DOUBLE, u.data());
  s.points.resize(static_cast<std::size_t>(num_points));
  for (hsize_t n = 0; n < num_nodes; ++n)
    if (point[n] >= 0)
      for (int d = 0; d < 3; ++d) s.points[point[n]][d] = static_cast<float>(mesh.nodes[n][d] + u[n][d]);
  return result;
}

QuadSurface body_surface(const QuadSurface& surface, std::int32_t body) {
  QuadSurface out;
  std::vector<std::int32_t> point(surface.points.size(), -1);
  for (std::size_t q = 0; q < surface.quads.size(); ++q)
    if (surface.body[q] == body)
      for (const std::int32_t p : surface.quads[q]) point[p] = 0;
  for (std::size_t p = 0; p < point.size(); ++p)
    if (point[p] == 0) {
      point[p] = static_cast<std::int32_t>(out.points.size());
      out.points.push_back(surface.points[p]);
    }
  for (std::size_t q = 0; q < surface.quads.size(); ++q)
    if (surface.body[q] == body) {
      const auto& c = surface.quads[q];
      out.quads.push_back({point[c[0]], point[c[1]], point[c[2]], point[c[3]]});
      out.body.push_back(body);
    }
  return out;
}

SurfaceExport export_surface(const std::string& h5_path, const std::string& vtp_path, std::int64_t step,
                             bool split_bodies) {
  const std::string suffix = ".vtp";
  if (vtp_path.size() <= suffix.size() || vtp_path.compare(vtp_path.size() - suffix.size(), suffix.size(), suffix) != 0)
    throw std::runtime_error("the output '" + vtp_path + "' must end in .vtp");
  const StepSurface read = read_step_surface(h5_path, step);
  SurfaceExport result;
  result.num_elements = read.num_elements;
  result.num_quads = static_cast<std::int64_t>(read.surface.quads.size());
  result.num_points = static_cast<std::int64_t>(read.surface.points.size());
  result.step = read.step;
  result.time = read.time;

  PendingFiles files;
  if (!split_bodies) {
    result.bytes += write_vtp(files.add(vtp_path), read.surface, read.time);
  } else {
    const std::string stem = vtp_path.substr(0, vtp_path.size() - suffix.size());
    const std::set<std::int32_t> bodies(read.surface.body.begin(), read.surface.body.end());
    std::vector<Block> blocks;
    std::set<std::string> taken;
    for (const std::int32_t b : bodies) {
      const bool named = b < static_cast<std::int32_t>(read.body_names.size()) && !read.body_names[b].empty();
      const std::string name = named ? read.body_names[b] : "body" + std::to_string(b);
      std::string path = stem + "_" + file_safe(name) + suffix;
      // Names that differ only in characters file_safe replaced would share a file.
      if (!taken.insert(path).second)
        taken.insert(path = stem + "_" + file_safe(name) + "_" + std::to_string(b) + suffix);
      result.bytes += write_vtp(files.add(path), body_surface(read.surface, b), read.time);
      blocks.push_back({name, std::filesystem::path(path).filename().string()});
    }
    result.bytes += write_vtm(files.add(stem + ".vtm"), blocks);
  }
  files.commit();
  result.files = files.paths();
  return result;
}

}  // namespace dipc
