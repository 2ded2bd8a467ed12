// dipc-surface (tools/surface_export.hpp) on output files written here with dipc's layout
// (io/xdmf_writer.hpp): two separate boxes, 3^3 and 2^3 hexes, of two bodies, and a 3^3 box
// with a corner hex removed (not convex). Checked: the quad count 6 n^2 of an n^3 box, every
// point used, outward orientation (the signed volume the quads enclose is the solid's, and each
// quad of a box faces away from its centre), the step's displacement applied; then the program
// itself: its .vtp and --split-bodies files read back (by the test and, where installed, by
// ParaView's pvpython), and errors that name the file and dataset and leave no file behind.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>

#include "mesh/box_generator.hpp"
#include "tools/surface_export.hpp"

namespace dipc {
namespace {

namespace fs = std::filesystem;

void write_dataset(hid_t file, const std::string& name, hid_t type, std::vector<hsize_t> dims, const void* data) {
  const hid_t space = H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr);
  const hid_t dataset = H5Dcreate2(file, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  ASSERT_GE(dataset, 0) << name;
  ASSERT_GE(H5Dwrite(dataset, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data), 0) << name;
  H5Dclose(dataset);
  H5Sclose(space);
}

struct Step {
  double time;
  std::vector<Vec3> displacement;
};

// The datasets dipc-surface reads, laid out as dipc's writer lays them out.
void write_output(const std::string& path, const HexMesh& mesh, const std::vector<std::string>& names,
                  const std::vector<Step>& steps) {
  const hid_t file = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  ASSERT_GE(file, 0) << path;
  for (const char* group : {"/mesh", "/steps"})
    H5Gclose(H5Gcreate2(file, group, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT));
  write_dataset(file, "/mesh/coordinates", H5T_NATIVE_DOUBLE, {mesh.nodes.size(), 3}, mesh.nodes.data());
  write_dataset(file, "/mesh/topology", H5T_NATIVE_INT64, {mesh.hexes.size(), 8}, mesh.hexes.data());
  write_dataset(file, "/mesh/body", H5T_NATIVE_INT, {mesh.body.size()}, mesh.body.data());
  std::size_t width = 1;
  for (const std::string& n : names) width = std::max(width, n.size() + 1);
  std::vector<char> text(names.size() * width, '\0');
  for (std::size_t i = 0; i < names.size(); ++i) std::memcpy(&text[i * width], names[i].data(), names[i].size());
  const hid_t string_type = H5Tcopy(H5T_C_S1);
  H5Tset_size(string_type, width);
  write_dataset(file, "/mesh/body_names", string_type, {names.size()}, text.data());
  H5Tclose(string_type);
  for (std::size_t k = 0; k < steps.size(); ++k) {
    const std::string group = "/steps/" + std::to_string(k);
    const hid_t g = H5Gcreate2(file, group.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    const hid_t scalar = H5Screate(H5S_SCALAR);
    const hid_t attribute = H5Acreate2(g, "time", H5T_NATIVE_DOUBLE, scalar, H5P_DEFAULT, H5P_DEFAULT);
    H5Awrite(attribute, H5T_NATIVE_DOUBLE, &steps[k].time);
    H5Aclose(attribute);
    H5Sclose(scalar);
    H5Gclose(g);
    write_dataset(file, group + "/displacement", H5T_NATIVE_DOUBLE, {mesh.nodes.size(), 3},
                  steps[k].displacement.data());
  }
  H5Fclose(file);
}

// An affine motion x -> A x + b with det A = 1.01 * 0.98 * 1.03, and its inverse.
Vec3 moved(const Vec3& x) { return {1.01 * x[0] + 0.5, 0.98 * x[1] - 0.25, 1.03 * x[2] + 0.125}; }
Vec3 unmoved(const std::array<float, 3>& p) {
  return {(p[0] - 0.5) / 1.01, (p[1] + 0.25) / 0.98, (p[2] - 0.125) / 1.03};
}
constexpr double kMovedVolume = 1.01 * 0.98 * 1.03;

// Two bodies: "cube", 3^3 unit hexes at the origin, and "small block", 2^3 at x = 10.
HexMesh two_boxes() {
  HexMesh mesh = generate_box({3, 3, 3}, {3, 3, 3}, {0, 0, 0}, 0, "cube");
  mesh.append(generate_box({2, 2, 2}, {2, 2, 2}, {10, 0, 0}, 1, "small"));
  return mesh;
}

std::vector<Step> rest_then_moved(const HexMesh& mesh) {
  Step rest{0.0, std::vector<Vec3>(mesh.nodes.size(), Vec3{0, 0, 0})}, later{0.5, {}};
  for (const Vec3& x : mesh.nodes) {
    const Vec3 y = moved(x);
    later.displacement.push_back({y[0] - x[0], y[1] - x[1], y[2] - x[2]});
  }
  return {rest, later};
}

std::string temp(const std::string& name) { return ::testing::TempDir() + "dipc_surface_" + name; }

Vec3 point(const QuadSurface& s, std::int32_t p) { return {s.points[p][0], s.points[p][1], s.points[p][2]}; }
Vec3 minus(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

// The volume the quads enclose by the divergence theorem, split into triangles (0,1,2) and
// (0,2,3): the solid's volume when every quad faces outward, negative when all face inward.
double signed_volume(const QuadSurface& s) {
  double v = 0;
  for (const auto& q : s.quads)
    v += (dot(point(s, q[0]), cross(point(s, q[1]), point(s, q[2]))) +
          dot(point(s, q[0]), cross(point(s, q[2]), point(s, q[3])))) /
         6;
  return v;
}

// Each quad's area vector (2x the diagonals' cross product / 2) against the direction from the
// centre of the (convex) solid to the quad's centroid.
void expect_facing_away_from(const QuadSurface& s, const Vec3& centre) {
  for (const auto& q : s.quads) {
    const Vec3 area = cross(minus(point(s, q[2]), point(s, q[0])), minus(point(s, q[3]), point(s, q[1])));
    Vec3 centroid{0, 0, 0};
    for (const std::int32_t p : q)
      for (int d = 0; d < 3; ++d) centroid[d] += s.points[p][d] / 4;
    EXPECT_GT(dot(area, minus(centroid, centre)), 0) << "quad " << q[0] << " " << q[1] << " " << q[2] << " " << q[3];
  }
}

void expect_every_point_used(const QuadSurface& s) {
  std::vector<int> uses(s.points.size(), 0);
  for (const auto& q : s.quads)
    for (const std::int32_t p : q) {
      ASSERT_GE(p, 0);
      ASSERT_LT(p, static_cast<std::int32_t>(s.points.size()));
      ++uses[p];
    }
  for (std::size_t p = 0; p < uses.size(); ++p) EXPECT_GT(uses[p], 0) << "point " << p;
}

TEST(SurfaceExport, TwoBoxesAtTheLastStep) {
  const HexMesh mesh = two_boxes();
  const std::string h5 = temp("two_boxes.h5");
  write_output(h5, mesh, {"cube", "small block"}, rest_then_moved(mesh));

  const StepSurface read = read_step_surface(h5, -1);
  EXPECT_EQ(read.step, 1);
  EXPECT_EQ(read.time, 0.5);
  EXPECT_EQ(read.num_elements, 27 + 8);
  EXPECT_EQ(read.body_names, (std::vector<std::string>{"cube", "small block"}));
  const QuadSurface& s = read.surface;
  EXPECT_EQ(s.quads.size(), 6u * 9 + 6u * 4);
  EXPECT_EQ(s.points.size(), (64u - 8) + (27u - 1));  // all nodes but the interior ones
  expect_every_point_used(s);
  // Every point is a moved boundary node: its preimage lies on a box face at integer coordinates.
  for (const auto& p : s.points) {
    const Vec3 x = unmoved(p);
    const double lo = x[0] < 5 ? 0 : 10, hi = x[0] < 5 ? 3 : 12;
    bool on_face = false;
    for (int d = 0; d < 3; ++d) {
      EXPECT_NEAR(x[d], std::round(x[d]), 1e-5);
      const double low = d == 0 ? lo : 0, high = d == 0 ? hi : hi - lo;
      on_face = on_face || std::abs(x[d] - low) < 1e-5 || std::abs(x[d] - high) < 1e-5;
    }
    EXPECT_TRUE(on_face) << x[0] << " " << x[1] << " " << x[2];
  }

  const QuadSurface cube = body_surface(s, 0), small = body_surface(s, 1);
  EXPECT_EQ(cube.quads.size(), 54u);
  EXPECT_EQ(cube.points.size(), 56u);
  EXPECT_EQ(small.quads.size(), 24u);
  EXPECT_EQ(small.points.size(), 26u);
  for (const std::int32_t b : small.body) EXPECT_EQ(b, 1);
  expect_every_point_used(cube);
  expect_every_point_used(small);
  EXPECT_NEAR(signed_volume(cube), 27 * kMovedVolume, 1e-4);
  EXPECT_NEAR(signed_volume(small), 8 * kMovedVolume, 1e-4);
  expect_facing_away_from(cube, moved({1.5, 1.5, 1.5}));
  expect_facing_away_from(small, moved({11, 1, 1}));
}

TEST(SurfaceExport, ChosenStep) {
  const HexMesh mesh = two_boxes();
  const std::string h5 = temp("two_boxes_step0.h5");
  write_output(h5, mesh, {"cube", "small block"}, rest_then_moved(mesh));
  const StepSurface read = read_step_surface(h5, 0);
  EXPECT_EQ(read.step, 0);
  EXPECT_EQ(read.time, 0.0);
  for (const auto& p : read.surface.points)
    for (int d = 0; d < 3; ++d) EXPECT_EQ(p[d], std::round(p[d]));  // the reference grid
  EXPECT_NEAR(signed_volume(read.surface), 27 + 8, 1e-9);
}

TEST(SurfaceExport, NonConvexSolid) {
  // A 3^3 box without its corner hex at (2,2,2): the notch's three faces become surface and
  // face into the notch; the corner node drops out, the box's centre node joins the surface.
  HexMesh mesh = generate_box({3, 3, 3}, {3, 3, 3}, {0, 0, 0}, 0, "notched");
  mesh.hexes.pop_back();
  mesh.body.pop_back();
  const std::string h5 = temp("notched.h5");
  write_output(h5, mesh, {"notched"}, rest_then_moved(mesh));
  const StepSurface read = read_step_surface(h5, -1);
  EXPECT_EQ(read.surface.quads.size(), 54u);
  EXPECT_EQ(read.surface.points.size(), 56u);
  expect_every_point_used(read.surface);
  EXPECT_NEAR(signed_volume(read.surface), 26 * kMovedVolume, 1e-4);
}

struct Outcome {
  int status;
  std::string output;  // stdout and stderr
};

Outcome run(const std::string& command_line) {
  FILE* pipe = popen((command_line + " 2>&1").c_str(), "r");
  Outcome o{-1, ""};
  if (!pipe) return o;
  char buffer[4096];
  std::size_t n;
  while ((n = fread(buffer, 1, sizeof buffer, pipe)) > 0) o.output.append(buffer, n);
  const int raw = pclose(pipe);
  o.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  return o;
}

Outcome surface(const std::string& arguments) { return run(std::string(DIPC_SURFACE) + " " + arguments); }

std::string contents(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// The appended arrays of a .vtp file by name ("" for the points), each as its raw bytes.
std::map<std::string, std::string> vtp_arrays(const std::string& path) {
  const std::string file = contents(path);
  const std::size_t start = file.find("_", file.find("<AppendedData")) + 1;
  std::map<std::string, std::string> arrays;
  const std::regex array("<DataArray type=\"\\w+\"(?: Name=\"(\\w+)\")?[^>]* offset=\"(\\d+)\"/>");
  const std::string header = file.substr(0, start);
  for (std::sregex_iterator m(header.begin(), header.end(), array), end; m != end; ++m) {
    const std::size_t at = start + std::stoull((*m)[2]);
    std::uint64_t bytes = 0;
    std::memcpy(&bytes, file.data() + at, sizeof bytes);
    arrays[(*m)[1]] = file.substr(at + sizeof bytes, bytes);
  }
  return arrays;
}

template <class T>
std::vector<T> values(const std::string& bytes) {
  std::vector<T> v(bytes.size() / sizeof(T));
  std::memcpy(v.data(), bytes.data(), v.size() * sizeof(T));
  return v;
}

TEST(SurfaceCli, WritesPolyDataAndSplitBodies) {
  const HexMesh mesh = two_boxes();
  const std::string h5 = temp("cli.h5"), vtp = temp("cli.vtp");
  write_output(h5, mesh, {"cube", "small block"}, rest_then_moved(mesh));
  for (const std::string& old : {vtp, temp("cli.vtm"), temp("cli_cube.vtp"), temp("cli_small_block.vtp")})
    fs::remove(old);

  Outcome o = surface(h5 + " " + vtp);
  ASSERT_EQ(o.status, 0) << o.output;
  EXPECT_NE(o.output.find("step 1 (t = 0.5): 35 elements, 78 surface quads, 82 surface nodes; " +
                          std::to_string(fs::file_size(vtp)) + " bytes -> " + vtp),
            std::string::npos)
      << o.output;
  auto arrays = vtp_arrays(vtp);
  EXPECT_EQ(values<double>(arrays["TimeValue"]), std::vector<double>{0.5});
  EXPECT_EQ(values<float>(arrays[""]).size(), 3u * 82);
  EXPECT_EQ(values<std::int32_t>(arrays["connectivity"]).size(), 4u * 78);
  const auto offsets = values<std::int32_t>(arrays["offsets"]);
  ASSERT_EQ(offsets.size(), 78u);
  EXPECT_EQ(offsets.back(), 4 * 78);
  const auto body = values<std::int32_t>(arrays["body"]);
  EXPECT_EQ(std::count(body.begin(), body.end(), 1), 24);

  o = surface(h5 + " " + vtp + " --step 0 --split-bodies");
  ASSERT_EQ(o.status, 0) << o.output;
  EXPECT_NE(o.output.find("step 0 (t = 0): 35 elements, 78 surface quads, 82 surface nodes;"), std::string::npos)
      << o.output;
  EXPECT_NE(o.output.find("-> " + temp("cli.vtm") + " + 2 .vtp"), std::string::npos) << o.output;
  EXPECT_NE(contents(temp("cli.vtm"))
                .find("<DataSet index=\"1\" name=\"small block\" file=\"dipc_surface_cli_small_block.vtp\"/>"),
            std::string::npos);
  arrays = vtp_arrays(temp("cli_small_block.vtp"));
  EXPECT_EQ(values<float>(arrays[""]).size(), 3u * 26);
  EXPECT_EQ(values<std::int32_t>(arrays["connectivity"]).size(), 4u * 24);
  for (const std::string& written : {vtp, temp("cli.vtm"), temp("cli_cube.vtp"), temp("cli_small_block.vtp")})
    EXPECT_FALSE(fs::exists(written + ".tmp")) << written;

#ifdef DIPC_PVPYTHON
  // ParaView's own readers: the cell and point counts of each file and block.
  const std::string script = temp("read.py");
  std::ofstream(script) << "import sys\n"
                           "from vtkmodules.vtkIOXML import vtkXMLPolyDataReader, vtkXMLMultiBlockDataReader\n"
                           "r = vtkXMLPolyDataReader(); r.SetFileName(sys.argv[1]); r.Update()\n"
                           "print('vtp', r.GetOutput().GetNumberOfCells(), r.GetOutput().GetNumberOfPoints())\n"
                           "m = vtkXMLMultiBlockDataReader(); m.SetFileName(sys.argv[2]); m.Update()\n"
                           "b = m.GetOutput()\n"
                           "for i in range(b.GetNumberOfBlocks()):\n"
                           "    print('block', b.GetMetaData(i).Get(b.NAME()), b.GetBlock(i).GetNumberOfCells(),\n"
                           "          b.GetBlock(i).GetNumberOfPoints())\n";
  o = run(std::string(DIPC_PVPYTHON) + " " + script + " " + vtp + " " + temp("cli.vtm"));
  ASSERT_EQ(o.status, 0) << o.output;
  EXPECT_NE(o.output.find("vtp 78 82\nblock cube 54 56\nblock small block 24 26\n"), std::string::npos) << o.output;
#endif
}

TEST(SurfaceCli, ErrorsNameTheFileAndLeaveNoOutput) {
  const HexMesh mesh = two_boxes();
  const std::string good = temp("good.h5"), vtp = temp("error.vtp");
  write_output(good, mesh, {"cube", "small block"}, rest_then_moved(mesh));
  const std::string no_topology = temp("no_topology.h5"), flat_topology = temp("flat_topology.h5");
  fs::copy_file(good, no_topology, fs::copy_options::overwrite_existing);
  fs::copy_file(good, flat_topology, fs::copy_options::overwrite_existing);
  for (const std::string& path : {no_topology, flat_topology}) {
    const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    H5Ldelete(file, "/mesh/topology", H5P_DEFAULT);
    if (path == flat_topology)
      write_dataset(file, "/mesh/topology", H5T_NATIVE_INT64, {2 * mesh.hexes.size(), 4}, mesh.hexes.data());
    H5Fclose(file);
  }
  const std::string not_hdf5 = temp("not_hdf5.h5");
  std::ofstream(not_hdf5) << "text\n";
  fs::remove(vtp);
  struct Case {
    std::string arguments, fragment;
  };
  const Case cases[] = {
      {temp("missing.h5") + " " + vtp, "dipc-surface: error: '" + temp("missing.h5") + "' does not exist"},
      {not_hdf5 + " " + vtp, "cannot open '" + not_hdf5 + "' as HDF5"},
      {no_topology + " " + vtp, "'" + no_topology + "' has no dataset /mesh/topology"},
      {flat_topology + " " + vtp,
       "dataset /mesh/topology in '" + flat_topology + "' has 70 x 4 entries, expected N x 8"},
      {good + " " + vtp + " --step 7", "'" + good + "' has no step 7 (last written step: 1)"},
      {good + " " + vtp + " --step -1", "--step: '-1' is neither a step number"},
      {good + " " + temp("error.vtk"), "must end in .vtp"},
      {good + " " + temp("no/such/dir.vtp"), "cannot create '" + temp("no/such/dir.vtp.tmp") + "'"},
      {good + " " + temp("no/such/dir.vtp") + " --split-bodies", "cannot create '" + temp("no/such/dir_cube.vtp.tmp")},
      {good, "expected an output .h5 file and a .vtp file to write"},
  };
  for (const Case& c : cases) {
    const Outcome o = surface(c.arguments);
    EXPECT_EQ(o.status, 1) << c.arguments << "\n" << o.output;
    EXPECT_NE(o.output.find(c.fragment), std::string::npos) << c.arguments << "\n" << o.output;
    EXPECT_FALSE(fs::exists(vtp)) << c.arguments;
    EXPECT_FALSE(fs::exists(vtp + ".tmp")) << c.arguments;
  }

  // A failed export leaves an earlier one as it was.
  ASSERT_EQ(surface(good + " " + vtp).status, 0);
  const std::string before = contents(vtp);
  EXPECT_EQ(surface(no_topology + " " + vtp).status, 1);
  EXPECT_EQ(contents(vtp), before);
}

}  // namespace
}  // namespace dipc
