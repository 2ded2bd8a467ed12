// Collective output tests (run on 1 and 2 ranks): each rank invents its block of a column of
// hexahedra, the writer stores mesh and two steps, and rank 0 reads the .h5 back with plain
// HDF5 and checks every value, then checks that the .xmf only refers to datasets that exist
// with the dimensions it states. StatsCsv is checked line by line.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <mpi.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <stdexcept>

#include "io/stats_csv.hpp"
#include "io/xdmf_writer.hpp"

namespace dipc {
namespace {

int comm_rank() {
  int r = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &r);
  return r;
}
int comm_size() {
  int s = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &s);
  return s;
}

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// A fresh directory shared by all ranks, removed after the test.
class OutputTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string path;
    if (comm_rank() == 0) {
      std::string pattern = (std::filesystem::temp_directory_path() / "dipc_io_test_XXXXXX").string();
      if (mkdtemp(pattern.data()) == nullptr) throw std::runtime_error("mkdtemp failed");
      path = pattern;
    }
    int length = static_cast<int>(path.size());
    MPI_Bcast(&length, 1, MPI_INT, 0, MPI_COMM_WORLD);
    path.resize(static_cast<std::size_t>(length));
    MPI_Bcast(path.data(), length, MPI_CHAR, 0, MPI_COMM_WORLD);
    dir_ = path;
  }
  void TearDown() override {
    MPI_Barrier(MPI_COMM_WORLD);
    if (comm_rank() == 0) std::filesystem::remove_all(dir_);
  }
  std::string dir_;
};

// A column of unit hexahedra stacked along z: element e joins node layers e and e + 1, layer
// L holds nodes 4L..4L+3 at the corners (0,0) (1,0) (1,1) (0,1) (Gmsh order). Rank r owns
// 2 + r elements and the node layers below them (the last rank also the top layer), so the
// blocks are uneven and each rank's last element has its top nodes owned by the next rank.
struct ColumnPart {
  std::int64_t global_elements = 0, element_offset = 0, global_nodes = 0, node_offset = 0;
  std::vector<double> coordinates;
  std::vector<std::int64_t> topology;
  std::vector<int> body;
  int owned_nodes() const { return static_cast<int>(coordinates.size() / 3); }
  int elements() const { return static_cast<int>(body.size()); }

  static std::array<double, 3> node_position(std::int64_t n) {
    const std::int64_t corner = n % 4;
    return {corner == 1 || corner == 2 ? 1.0 : 0.0, corner >= 2 ? 1.0 : 0.0, 0.5 * static_cast<double>(n / 4)};
  }
  static int element_body(std::int64_t e) { return static_cast<int>(e % 2); }
  static double displacement(int step, std::int64_t n, int c) { return 1000.0 * step + 10.0 * n + c; }
  static double velocity(int step, std::int64_t n, int c) { return -displacement(step, n, c) - 0.5; }
  static double volume_ratio(int step, std::int64_t e) { return 1.0 + 0.01 * e + step; }

  ColumnPart(int rank, int size) {
    for (int r = 0; r < size; ++r) {
      if (r < rank) element_offset += 2 + r;
      global_elements += 2 + r;
    }
    global_nodes = 4 * (global_elements + 1);
    node_offset = 4 * element_offset;
    const std::int64_t count = 2 + rank;
    const std::int64_t owned_layers = count + (rank == size - 1 ? 1 : 0);
    for (std::int64_t n = node_offset; n < node_offset + 4 * owned_layers; ++n) {
      for (double x : node_position(n)) coordinates.push_back(x);
    }
    for (std::int64_t e = element_offset; e < element_offset + count; ++e) {
      for (int k = 0; k < 8; ++k) topology.push_back(4 * (e + k / 4) + k % 4);
      body.push_back(element_body(e));
    }
  }

  OutputMesh output_mesh() const {
    OutputMesh m;
    m.comm = MPI_COMM_WORLD;
    m.num_global_nodes = global_nodes;
    m.node_offset = node_offset;
    m.num_owned_nodes = owned_nodes();
    m.owned_coordinates = coordinates.data();
    m.num_global_elements = global_elements;
    m.element_offset = element_offset;
    m.num_elements = elements();
    m.element_nodes = topology.data();
    m.element_body = body.data();
    return m;
  }

  void write_step(XdmfWriter& writer, int step, double time) const {
    std::vector<double> u, v, ratio;
    for (std::int64_t n = node_offset; n < node_offset + owned_nodes(); ++n) {
      for (int c = 0; c < 3; ++c) {
        u.push_back(displacement(step, n, c));
        v.push_back(velocity(step, n, c));
      }
    }
    for (std::int64_t e = element_offset; e < element_offset + elements(); ++e) ratio.push_back(volume_ratio(step, e));
    StepFields fields;
    fields.time = time;
    fields.displacement = u.data();
    fields.velocity = v.data();
    fields.volume_ratio = ratio.data();
    writer.write_step(fields);
  }
};

// A dataset read whole: its dimensions and values (converted by HDF5 to T).
template <typename T>
struct Dataset {
  std::vector<hsize_t> dims;
  std::vector<T> values;
};

template <typename T>
Dataset<T> read_dataset(hid_t file, const std::string& path, hid_t memory_type) {
  Dataset<T> out;
  const hid_t dataset = H5Dopen2(file, path.c_str(), H5P_DEFAULT);
  if (dataset < 0) throw std::runtime_error("no dataset " + path);
  const hid_t space = H5Dget_space(dataset);
  out.dims.resize(static_cast<std::size_t>(H5Sget_simple_extent_ndims(space)));
  H5Sget_simple_extent_dims(space, out.dims.data(), nullptr);
  out.values.resize(static_cast<std::size_t>(H5Sget_simple_extent_npoints(space)));
  const herr_t status = H5Dread(dataset, memory_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.values.data());
  H5Sclose(space);
  H5Dclose(dataset);
  if (status < 0) throw std::runtime_error("cannot read " + path);
  return out;
}

std::vector<hsize_t> dims(std::initializer_list<std::int64_t> d) { return {d.begin(), d.end()}; }

// Rank 0: every value in the file is the one the ranks wrote.
void check_h5_contents(const std::string& path, std::int64_t nodes, std::int64_t elements,
                       const std::vector<double>& times) {
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(file, 0) << path;

  const auto coordinates = read_dataset<double>(file, "/mesh/coordinates", H5T_NATIVE_DOUBLE);
  EXPECT_EQ(coordinates.dims, dims({nodes, 3}));
  for (std::int64_t n = 0; n < nodes; ++n) {
    for (int c = 0; c < 3; ++c) EXPECT_EQ(coordinates.values[3 * n + c], ColumnPart::node_position(n)[c]) << n;
  }
  const auto topology = read_dataset<std::int64_t>(file, "/mesh/topology", H5T_NATIVE_INT64);
  EXPECT_EQ(topology.dims, dims({elements, 8}));
  for (std::int64_t e = 0; e < elements; ++e) {
    for (int k = 0; k < 8; ++k) EXPECT_EQ(topology.values[8 * e + k], 4 * (e + k / 4) + k % 4);
  }
  const auto body = read_dataset<int>(file, "/mesh/body", H5T_NATIVE_INT);
  const auto rank = read_dataset<int>(file, "/mesh/rank", H5T_NATIVE_INT);
  EXPECT_EQ(body.dims, dims({elements}));
  EXPECT_EQ(rank.dims, dims({elements}));
  for (std::int64_t e = 0, first = 0, r = 0; e < elements; ++e) {
    if (e == first + 2 + r) first += 2 + r++;  // rank r holds 2 + r elements
    EXPECT_EQ(body.values[e], ColumnPart::element_body(e));
    EXPECT_EQ(rank.values[e], r) << "element " << e;
  }

  for (std::size_t s = 0; s < times.size(); ++s) {
    const std::string group = "/steps/" + std::to_string(s);
    const int step = static_cast<int>(s);
    const auto u = read_dataset<double>(file, group + "/displacement", H5T_NATIVE_DOUBLE);
    const auto v = read_dataset<double>(file, group + "/velocity", H5T_NATIVE_DOUBLE);
    const auto ratio = read_dataset<double>(file, group + "/volume_ratio", H5T_NATIVE_DOUBLE);
    EXPECT_EQ(u.dims, dims({nodes, 3}));
    EXPECT_EQ(v.dims, dims({nodes, 3}));
    EXPECT_EQ(ratio.dims, dims({elements}));
    for (std::int64_t n = 0; n < nodes; ++n) {
      for (int c = 0; c < 3; ++c) {
        EXPECT_EQ(u.values[3 * n + c], ColumnPart::displacement(step, n, c));
        EXPECT_EQ(v.values[3 * n + c], ColumnPart::velocity(step, n, c));
      }
    }
    for (std::int64_t e = 0; e < elements; ++e) EXPECT_EQ(ratio.values[e], ColumnPart::volume_ratio(step, e));

    double time = -1;
    const hid_t attribute = H5Aopen_by_name(file, group.c_str(), "time", H5P_DEFAULT, H5P_DEFAULT);
    ASSERT_GE(attribute, 0) << group;
    H5Aread(attribute, H5T_NATIVE_DOUBLE, &time);
    H5Aclose(attribute);
    EXPECT_EQ(time, times[s]);
  }
  H5Fclose(file);
}

// Rank 0: the .xmf has one grid per step with the right times, and every DataItem names a
// dataset of the .h5 next to it with exactly the dimensions stated.
void check_xdmf_against_h5(const std::string& xmf_path, const std::string& h5_name, const std::string& h5_path,
                           const std::vector<double>& times, int items_per_step = 7, int grids_per_step = 1) {
  const std::string xmf = read_text(xmf_path);
  ASSERT_NE(xmf.find("GridType=\"Collection\" CollectionType=\"Temporal\""), std::string::npos) << xmf;
  EXPECT_FALSE(std::filesystem::exists(xmf_path + ".tmp"));

  const std::regex time_re("<Time Value=\"([^\"]*)\"/>");
  std::vector<double> listed;
  for (auto it = std::sregex_iterator(xmf.begin(), xmf.end(), time_re); it != std::sregex_iterator(); ++it) {
    listed.push_back(std::stod((*it)[1]));
  }
  EXPECT_EQ(listed, times);
  const std::regex grid_re("<Grid Name=\"[^\"]*\" GridType=\"Uniform\">");
  EXPECT_EQ(std::distance(std::sregex_iterator(xmf.begin(), xmf.end(), grid_re), std::sregex_iterator()),
            static_cast<std::ptrdiff_t>(grids_per_step * times.size()));

  const hid_t file = H5Fopen(h5_path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(file, 0);
  const std::regex item_re("<DataItem Dimensions=\"([^\"]*)\"[^>]*Format=\"HDF\">([^:<]*):([^<]*)</DataItem>");
  int items = 0;
  for (auto it = std::sregex_iterator(xmf.begin(), xmf.end(), item_re); it != std::sregex_iterator(); ++it, ++items) {
    const std::string stated = (*it)[1], file_name = (*it)[2], dataset_path = (*it)[3];
    EXPECT_EQ(file_name, h5_name);
    ASSERT_GT(H5Lexists(file, dataset_path.c_str(), H5P_DEFAULT), 0) << dataset_path;
    const hid_t dataset = H5Dopen2(file, dataset_path.c_str(), H5P_DEFAULT);
    const hid_t space = H5Dget_space(dataset);
    std::vector<hsize_t> d(static_cast<std::size_t>(H5Sget_simple_extent_ndims(space)));
    H5Sget_simple_extent_dims(space, d.data(), nullptr);
    H5Sclose(space);
    H5Dclose(dataset);
    std::string actual;
    for (hsize_t x : d) actual += (actual.empty() ? "" : " ") + std::to_string(x);
    EXPECT_EQ(stated, actual) << dataset_path;
  }
  H5Fclose(file);
  EXPECT_EQ(items, items_per_step * static_cast<int>(times.size()));  // default: topology, geometry, 5 attributes
}

bool text_has_grid(const std::string& xmf_path, const std::string& name) {
  return read_text(xmf_path).find("<Grid Name=\"" + name + "\" GridType=\"Uniform\">") != std::string::npos;
}

TEST_F(OutputTest, WritesMeshAndStepsCollectively) {
  const ColumnPart part(comm_rank(), comm_size());
  const std::string out_dir = dir_ + "/nested/out";  // created by the writer (mkdir -p)
  const std::vector<double> times = {0.01, 0.02};
  std::string h5, xmf;
  {
    XdmfWriter writer(out_dir, "column", part.output_mesh());
    h5 = writer.h5_path();
    xmf = writer.xdmf_path();
    EXPECT_EQ(h5, out_dir + "/column.h5");
    EXPECT_EQ(xmf, out_dir + "/column.xmf");
    MPI_Barrier(MPI_COMM_WORLD);
    if (comm_rank() == 0) check_xdmf_against_h5(xmf, "column.h5", h5, {});  // valid before any step

    part.write_step(writer, 0, times[0]);
    MPI_Barrier(MPI_COMM_WORLD);
    if (comm_rank() == 0) check_xdmf_against_h5(xmf, "column.h5", h5, {times[0]});  // file still open

    part.write_step(writer, 1, times[1]);
    EXPECT_EQ(writer.num_steps_written(), 2u);
  }
  if (comm_rank() == 0) {
    check_h5_contents(h5, part.global_nodes, part.global_elements, times);
    check_xdmf_against_h5(xmf, "column.h5", h5, times);
  }
}

// The fields of contact scenes: body names, kinematic flags, contact and friction forces, the
// active pairs per kind, and obstacles as their own grids (a fixed quad, a moving triangle
// pair written by rank 0 only). Values are read back; the .xmf must point at each of them.
TEST_F(OutputTest, WritesContactFieldsAndObstacleGrids) {
  const ColumnPart part(comm_rank(), comm_size());
  OutputMesh mesh = part.output_mesh();
  mesh.body_names = {"lower", "upper & <top>"};  // escaped in the .xmf
  std::vector<int> kinematic;
  for (int b : part.body) kinematic.push_back(b == 1 ? 1 : 0);
  mesh.element_kinematic = kinematic.data();
  mesh.contact_force = mesh.friction_force = true;
  mesh.contact_pair_kinds = {"point_plane", "edge_edge"};
  OutputObstacle quad{"plane0", "plane", 4, {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0}, {0, 1, 2, 3}, false};
  OutputObstacle tri{"ramp", "triangle_mesh", 3, {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 1}, {0, 1, 2, 0, 2, 3}, true};
  mesh.obstacles = {quad, tri};
  const auto force = [](int step, std::int64_t n, int c, double sign) { return sign * (step + 0.25 * n + 0.5 * c); };
  std::string h5, xmf;
  {
    XdmfWriter writer(dir_, "fields", mesh);
    h5 = writer.h5_path();
    xmf = writer.xdmf_path();
    for (int step = 0; step < 2; ++step) {
      std::vector<double> u, v, fc, ff, ratio;
      for (std::int64_t n = part.node_offset; n < part.node_offset + part.owned_nodes(); ++n)
        for (int c = 0; c < 3; ++c) {
          u.push_back(ColumnPart::displacement(step, n, c));
          v.push_back(ColumnPart::velocity(step, n, c));
          fc.push_back(force(step, n, c, 1));
          ff.push_back(force(step, n, c, -1));
        }
      for (std::int64_t e = part.element_offset; e < part.element_offset + part.elements(); ++e)
        ratio.push_back(ColumnPart::volume_ratio(step, e));
      StepFields fields;
      fields.time = 0.5 * step;
      fields.displacement = u.data();
      fields.velocity = v.data();
      fields.volume_ratio = ratio.data();
      fields.contact_force = fc.data();
      fields.friction_force = ff.data();
      fields.contact_pairs = {7 + step, 3};
      // Only rank 0's copy is written: the others pass garbage of the right size.
      fields.obstacle_displacement = {std::vector<double>(12, comm_rank() == 0 ? 0.1 * step : -99.0)};
      writer.write_step(fields);
    }
    // A step without a field the mesh announced fails on every rank.
    StepFields missing;
    missing.time = 1.0;
    EXPECT_THROW(writer.write_step(missing), std::runtime_error);
  }
  if (comm_rank() != 0) return;
  // Bodies e % 2 are runs of rows only on one rank (2 elements): there the kinematic body is its
  // own grid; with more elements they interleave and the mesh stays one grid.
  const int body_grids = part.global_elements == 2 ? 2 : 1;
  // A bodies' grid: topology, geometry, 2 node + 2 force + 4 cell attributes; quad and triangles: 3 each.
  check_xdmf_against_h5(xmf, "fields.h5", h5, {0.0, 0.5}, 10 * body_grids + 3 + 3, body_grids + 2);
  EXPECT_EQ(text_has_grid(xmf, "bodies"), body_grids == 1);
  const std::string text = read_text(xmf);
  EXPECT_NE(text.find("CollectionType=\"Spatial\""), std::string::npos);
  EXPECT_NE(text.find("Value=\"lower, upper &amp; &lt;top&gt;\""), std::string::npos);
  EXPECT_NE(text.find("<Grid Name=\"ramp\" GridType=\"Uniform\">"), std::string::npos);
  EXPECT_NE(text.find("TopologyType=\"Quadrilateral\""), std::string::npos);

  const hid_t file = H5Fopen(h5.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(file, 0);
  {  // body names: fixed-length strings, one per body id
    const hid_t dataset = H5Dopen2(file, "/mesh/body_names", H5P_DEFAULT);
    ASSERT_GE(dataset, 0);
    const hid_t type = H5Dget_type(dataset);
    const std::size_t width = H5Tget_size(type);
    std::vector<char> buffer(2 * width);
    H5Dread(dataset, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, buffer.data());
    EXPECT_EQ(std::string(buffer.data()), "lower");
    EXPECT_EQ(std::string(buffer.data() + width), "upper & <top>");
    H5Tclose(type);
    H5Dclose(dataset);
  }
  const auto flags = read_dataset<int>(file, "/mesh/kinematic", H5T_NATIVE_INT);
  for (std::int64_t e = 0; e < part.global_elements; ++e) EXPECT_EQ(flags.values[e], ColumnPart::element_body(e));
  for (int step = 0; step < 2; ++step) {
    const std::string group = "/steps/" + std::to_string(step);
    const auto fc = read_dataset<double>(file, group + "/contact_force", H5T_NATIVE_DOUBLE);
    const auto ff = read_dataset<double>(file, group + "/friction_force", H5T_NATIVE_DOUBLE);
    for (std::int64_t n = 0; n < part.global_nodes; ++n)
      for (int c = 0; c < 3; ++c) {
        EXPECT_EQ(fc.values[3 * n + c], force(step, n, c, 1));
        EXPECT_EQ(ff.values[3 * n + c], force(step, n, c, -1));
      }
    for (const auto& [name, expected] :
         {std::pair<const char*, long long>{"contact_pairs_point_plane", 7 + step}, {"contact_pairs_edge_edge", 3}}) {
      long long count = -1;
      const hid_t attribute = H5Aopen_by_name(file, group.c_str(), name, H5P_DEFAULT, H5P_DEFAULT);
      ASSERT_GE(attribute, 0) << group << " " << name;
      H5Aread(attribute, H5T_NATIVE_LLONG, &count);
      H5Aclose(attribute);
      EXPECT_EQ(count, expected) << name;
    }
    const auto moved = read_dataset<double>(file, group + "/obstacles/1/displacement", H5T_NATIVE_DOUBLE);
    EXPECT_EQ(moved.dims, dims({4, 3}));
    for (double u : moved.values) EXPECT_EQ(u, 0.1 * step);
  }
  EXPECT_EQ(H5Lexists(file, "/steps/0/obstacles/0", H5P_DEFAULT), 0);  // the quad does not move
  const auto quad_u = read_dataset<double>(file, "/obstacles/0/displacement", H5T_NATIVE_DOUBLE);
  for (double u : quad_u.values) EXPECT_EQ(u, 0.0);
  const auto ramp = read_dataset<std::int64_t>(file, "/obstacles/1/topology", H5T_NATIVE_INT64);
  EXPECT_EQ(ramp.dims, dims({2, 3}));
  EXPECT_EQ(ramp.values, (std::vector<std::int64_t>{0, 1, 2, 0, 2, 3}));
  H5Fclose(file);
}

// Kinematic bodies become their own grids: each kinematic body one grid, the other bodies runs
// of consecutive rows, every grid a HyperSlab of the mesh's cell datasets. Elements 0..4 (5 on
// 2 ranks, 2 on 1) belong to bodies A, K (kinematic), B, B, C: 2 ranks give A, K and "B..C".
// (WritesContactFieldsAndObstacleGrids covers interleaved bodies: one grid, as without.)
TEST_F(OutputTest, KinematicBodiesAreTheirOwnGrids) {
  const ColumnPart part(comm_rank(), comm_size());
  OutputMesh mesh = part.output_mesh();
  const int body_of[] = {0, 1, 2, 2, 3};
  std::vector<int> body, kinematic;
  for (std::int64_t e = part.element_offset; e < part.element_offset + part.elements(); ++e) {
    body.push_back(body_of[e]);
    kinematic.push_back(body_of[e] == 1 ? 1 : 0);
  }
  mesh.element_body = body.data();
  mesh.element_kinematic = kinematic.data();
  mesh.body_names = {"A", "K", "B", "C"};
  std::string h5, xmf;
  {
    XdmfWriter writer(dir_, "kinematic", mesh);
    h5 = writer.h5_path();
    xmf = writer.xdmf_path();
    part.write_step(writer, 0, 0.5);
  }
  if (comm_rank() != 0) return;
  const std::string text = read_text(xmf);
  const bool two = part.global_elements == 5;
  const std::vector<std::string> names = two ? std::vector<std::string>{"A", "K", "B..C"}
                                             : std::vector<std::string>{"A", "K"};
  // Per grid: topology (a HyperSlab of one dataset), geometry, 2 node and 4 cell attributes.
  check_xdmf_against_h5(xmf, "kinematic.h5", h5, {0.5}, 8 * static_cast<int>(names.size()),
                        static_cast<int>(names.size()));
  std::size_t at = 0;
  for (const std::string& name : names) {
    at = text.find("<Grid Name=\"" + name + "\" GridType=\"Uniform\">", at);
    EXPECT_NE(at, std::string::npos) << name << " missing or out of order:\n" << text;
  }
  EXPECT_NE(text.find("<Grid Name=\"step_0\" GridType=\"Collection\" CollectionType=\"Spatial\">"), std::string::npos);
  // K is row 1 of the cells: its topology selects that row, its cell fields are its own rows.
  EXPECT_NE(text.find("<DataItem Dimensions=\"3 2\" Format=\"XML\">1 0 1 1 1 8</DataItem>"), std::string::npos) << text;
  EXPECT_NE(text.find(
                "Dimensions=\"1\" NumberType=\"Int\" Precision=\"4\" Format=\"HDF\">kinematic.h5:/mesh/grids/1/body<"),
            std::string::npos)
      << text;
  if (two) {
    EXPECT_NE(text.find(">2 0 1 1 3 8</DataItem>"), std::string::npos) << text;
  }
  // Each grid's rows of the cell fields equal the whole mesh's rows.
  const hid_t file = H5Fopen(h5.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(file, 0);
  const auto all_bodies = read_dataset<int>(file, "/mesh/body", H5T_NATIVE_INT);
  const auto all_ratios = read_dataset<double>(file, "/steps/0/volume_ratio", H5T_NATIVE_DOUBLE);
  const std::vector<std::pair<std::int64_t, std::int64_t>> rows = {{0, 1}, {1, 1}, {2, 3}};
  for (std::size_t g = 0; g < names.size(); ++g) {
    const std::string grid = "/grids/" + std::to_string(g);
    const auto body = read_dataset<int>(file, "/mesh" + grid + "/body", H5T_NATIVE_INT);
    const auto flag = read_dataset<int>(file, "/mesh" + grid + "/kinematic", H5T_NATIVE_INT);
    const auto ratio = read_dataset<double>(file, "/steps/0" + grid + "/volume_ratio", H5T_NATIVE_DOUBLE);
    ASSERT_EQ(body.values.size(), static_cast<std::size_t>(rows[g].second)) << names[g];
    for (std::int64_t r = 0; r < rows[g].second; ++r) {
      EXPECT_EQ(body.values[r], all_bodies.values[rows[g].first + r]) << names[g];
      EXPECT_EQ(flag.values[r], all_bodies.values[rows[g].first + r] == 1 ? 1 : 0) << names[g];
      EXPECT_EQ(ratio.values[r], all_ratios.values[rows[g].first + r]) << names[g];
    }
  }
  H5Fclose(file);
}

// Every rank must see the exception, or the others would wait in the next collective call.
TEST_F(OutputTest, UncreatableDirectoryThrowsOnEveryRank) {
  const ColumnPart part(comm_rank(), comm_size());
  const std::string blocker = dir_ + "/a_file";
  if (comm_rank() == 0) std::ofstream(blocker) << "not a directory";
  MPI_Barrier(MPI_COMM_WORLD);
  try {
    XdmfWriter writer(blocker + "/out", "column", part.output_mesh());
    ADD_FAILURE() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("cannot create output directory '" + blocker + "/out'"), std::string::npos)
        << e.what();
  }
}

TEST_F(OutputTest, Hdf5FailureThrowsOnEveryRankNamingTheFile) {
  const ColumnPart part(comm_rank(), comm_size());
  if (comm_rank() == 0) std::filesystem::create_directories(dir_ + "/column.h5");  // blocks the file
  MPI_Barrier(MPI_COMM_WORLD);
  try {
    XdmfWriter writer(dir_, "column", part.output_mesh());
    ADD_FAILURE() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("cannot create HDF5 file '" + dir_ + "/column.h5'"), std::string::npos)
        << e.what();
  }
}

TEST_F(OutputTest, InconsistentPartsThrowOnEveryRank) {
  const ColumnPart part(comm_rank(), comm_size());
  OutputMesh mesh = part.output_mesh();
  mesh.num_global_nodes += 1;
  try {
    XdmfWriter writer(dir_, "column", mesh);
    ADD_FAILURE() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("nodes: local counts sum to"), std::string::npos) << e.what();
  }
  if (comm_size() > 1) {
    mesh = part.output_mesh();
    if (comm_rank() == 1) mesh.element_offset += 1;
    try {
      XdmfWriter writer(dir_, "column", mesh);
      ADD_FAILURE() << "no exception";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find("elements: offset 3 on rank 1 should be 2"), std::string::npos) << e.what();
    }
  }
}

TEST_F(OutputTest, StatsCsvWritesHeaderAndRows) {
  const std::string path = dir_ + "/run/stats.csv";
  {
    StatsCsv stats(path, {"step", "time", "newton_iterations"});
    EXPECT_EQ(stats.columns().size(), 3u);
    stats.row({1, 0.01, 3});
    MPI_Barrier(MPI_COMM_WORLD);
    // Flushed per row: readable while the run goes on.
    if (comm_rank() == 0) {
      EXPECT_EQ(read_text(path), "step,time,newton_iterations\n1,0.01,3\n");
    }
    stats.row({2, 1.0 / 3.0, 1e-20});
    EXPECT_THROW(stats.row({3, 0.03}), std::invalid_argument);
  }
  MPI_Barrier(MPI_COMM_WORLD);
  if (comm_rank() == 0) {
    EXPECT_EQ(read_text(path), "step,time,newton_iterations\n1,0.01,3\n2,0.3333333333,1e-20\n");
  }
}

TEST_F(OutputTest, StatsCsvErrorsNameThePath) {
  const std::string blocker = dir_ + "/a_file";
  if (comm_rank() == 0) std::ofstream(blocker) << "not a directory";
  MPI_Barrier(MPI_COMM_WORLD);
  try {
    StatsCsv stats(blocker + "/stats.csv", {"step"});
    ADD_FAILURE() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("cannot create '" + blocker + "/stats.csv'"), std::string::npos) << e.what();
  }
  EXPECT_THROW(StatsCsv(dir_ + "/s.csv", {"a,b"}), std::invalid_argument);
}

}  // namespace
}  // namespace dipc
