// Bad input end to end: each malformed scene, mesh, option or options file makes `dipc` exit
// with status 1 and one clear message that names the file and the key, element, node, bodies or
// option — and no PETSc error trace — on 1 and 2 ranks.
#include <gtest/gtest.h>

#include <hdf5.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "support/source_tree.hpp"

namespace {

struct Outcome {
  int status;
  std::string output;
};

// Inputs that the tests write before they run (GeneratedInputs below): directories in place of
// mesh files, which git cannot hold, and scenes too small to be worth a data file.
const std::string generated_dir = "generated_inputs/";

// `dipc <data file> -dipc_no_output -dipc_quiet <extra>` on `ranks` ranks (mpiexec for 2); a
// scene under generated_dir is taken from there.
Outcome run_dipc(const std::string& scene, const std::string& extra = "", int ranks = 1) {
  const std::string launcher = ranks > 1 ? std::string(DIPC_MPIEXEC) + " -n " + std::to_string(ranks) + " " : "";
  const bool generated = scene.rfind(generated_dir, 0) == 0;
  const std::string path = generated ? scene : dipc::test::source_dir() + "/tests/app/data/" + scene;
  const std::string cmd = launcher + DIPC_BINARY + " " + path + " -dipc_no_output -dipc_quiet " + extra + " 2>&1";
  Outcome o{-1, ""};
  FILE* pipe = popen(cmd.c_str(), "r");
  if (!pipe) return o;
  std::array<char, 4096> buf;
  while (std::fgets(buf.data(), buf.size(), pipe)) o.output += buf.data();
  const int raw = pclose(pipe);
  o.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  return o;
}

struct BadInput {
  const char* name;                   // the test's name
  std::string scene;                  // under tests/app/data/, or generated_dir
  std::string extra;                  // more arguments
  std::vector<std::string> expected;  // substrings of the message
};

const std::string data_dir = dipc::test::source_dir() + "/tests/app/data/";

// Bad checkpoints for -dipc_restart, made before the tests run from a real one (one step of
// small_box.json): truncated (its first half), corrupt (one byte of /nodes/position's data
// changed, found with H5Dget_offset), foreign (an HDF5 file without dipc's format attribute,
// and a file that is not HDF5 at all), mismatched (read with another scene).
const std::string bad_dir = "bad_checkpoints";
const std::string good_checkpoint = bad_dir + "/run/dipc.checkpoint.000001.h5";

std::string read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

void write_bytes(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
}

class BadCheckpoints : public ::testing::Environment {
 public:
  void SetUp() override {
    std::filesystem::remove_all(bad_dir);
    const std::string cmd = std::string(DIPC_BINARY) + " " + data_dir +
                            "small_box.json -dipc_quiet -dipc_steps 1 "
                            "-dipc_checkpoint_every 1 -dipc_output " +
                            bad_dir + "/run > /dev/null 2>&1";
    ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
    const std::string good = read_bytes(good_checkpoint);
    ASSERT_GT(good.size(), 1000u);
    write_bytes(bad_dir + "/truncated.h5", good.substr(0, good.size() / 2));
    // Corrupt: flip one byte of the position data, where HDF5 reads it back without complaint.
    hid_t file = H5Fopen(good_checkpoint.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    hid_t dataset = H5Dopen2(file, "/nodes/position", H5P_DEFAULT);
    const haddr_t offset = H5Dget_offset(dataset);
    H5Dclose(dataset);
    H5Fclose(file);
    ASSERT_NE(offset, HADDR_UNDEF);
    std::string corrupt = good;
    corrupt[offset + 5] = static_cast<char>(corrupt[offset + 5] ^ 0x10);
    write_bytes(bad_dir + "/corrupt.h5", corrupt);
    // Foreign: an HDF5 file of someone else's.
    file = H5Fcreate((bad_dir + "/foreign.h5").c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    const hsize_t n = 4;
    const double values[4] = {1, 2, 3, 4};
    hid_t space = H5Screate_simple(1, &n, nullptr);
    dataset = H5Dcreate2(file, "values", H5T_IEEE_F64LE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    H5Dwrite(dataset, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values);
    H5Dclose(dataset);
    H5Sclose(space);
    H5Fclose(file);
  }
};

[[maybe_unused]] ::testing::Environment* const bad_checkpoints = ::testing::AddGlobalTestEnvironment(
    new BadCheckpoints);

// A one-body scene: `body` is the body's source ("box": {...} or "mesh": "..."), `dt` the step,
// `more` further top-level keys (with their leading comma).
std::string one_body_scene(const std::string& body, const std::string& dt = "0.01", const std::string& more = "") {
  return R"({"materials": [{"name": "rubber", "E": 1e6, "nu": 0.4, "rho": 1000}],
  "geometry": [{"name": "block", )" +
         body + R"(, "material": "rubber"}],
  "boundary_conditions": {"gravity": [0, 0, -9.81]}, "time": {"dt": )" +
         dt + R"(, "steps": 2})" + more + "}\n";
}

void write_text(const std::string& path, const std::string& text) { std::ofstream(path, std::ios::trunc) << text; }

// A dipc HDF5 mesh of one unit hexahedron whose node 2 has a NaN y coordinate.
void write_nan_y_mesh(const std::string& path) {
  double x[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  x[2][1] = std::nan("");
  const std::int64_t hex[8] = {0, 1, 2, 3, 4, 5, 6, 7};
  hid_t file = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  hid_t group = H5Gcreate2(file, "/mesh", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  const hsize_t coordinates[2] = {8, 3}, topology[2] = {1, 8};
  hid_t space = H5Screate_simple(2, coordinates, nullptr);
  hid_t dataset = H5Dcreate2(file, "/mesh/coordinates", H5T_IEEE_F64LE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  H5Dwrite(dataset, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, x);
  H5Dclose(dataset);
  H5Sclose(space);
  space = H5Screate_simple(2, topology, nullptr);
  dataset = H5Dcreate2(file, "/mesh/topology", H5T_STD_I64LE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  H5Dwrite(dataset, H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, hex);
  H5Dclose(dataset);
  H5Sclose(space);
  H5Gclose(group);
  H5Fclose(file);
}

class GeneratedInputs : public ::testing::Environment {
 public:
  void SetUp() override {
    std::filesystem::remove_all(generated_dir);
    for (const char* directory : {"dir.msh", "dir.h5", "dir.obj"})
      std::filesystem::create_directories(generated_dir + directory);
    const std::string box = R"("box": {"size": [0.2, 0.1, 0.1], "resolution": [2, 1, 1]})";
    write_text(generated_dir + "directory_msh.json", one_body_scene(R"("mesh": "dir.msh")"));
    write_text(generated_dir + "directory_h5.json", one_body_scene(R"("mesh": "dir.h5")"));
    write_text(
        generated_dir + "directory_obj.json",
        one_body_scene(box, "0.01",
                       R"(, "contact": {"enabled": true, "obstacles": [{"name": "floor", "mesh": "dir.obj"}]})"));
    write_nan_y_mesh(generated_dir + "nan_y.h5");
    write_text(generated_dir + "nan_y_hdf5.json", one_body_scene(R"("mesh": "nan_y.h5")"));
    write_text(generated_dir + "tiny_dt.json", one_body_scene(box, "1e-300"));
    write_text(generated_dir + "huge_box.json",
               one_body_scene(R"("box": {"size": [0.2, 0.1, 0.1], "resolution": [100000, 100000, 100000]})"));
    write_text(generated_dir + "big_box.json",
               one_body_scene(R"("box": {"size": [0.2, 0.1, 0.1], "resolution": [1300, 1300, 1300]})"));
    write_text(generated_dir + "flat_box.json",
               one_body_scene(R"("box": {"size": [0.2, 0.1, 1e-30], "resolution": [2, 1, 1]})", "0.01",
                              R"(, "contact": {"enabled": true})"));
    // PolyFEM's transformation.dimensions with a size 0 along an axis where the obstacle is not
    // flat (floor_y.obj spans 0.5 m along z): PolyFEM would flatten it into zero-area triangles.
    const std::string polyfem = data_dir + "polyfem/";
    write_text(generated_dir + "polyfem_flattened_obstacle.json", R"({"geometry": [{"mesh": ")" + polyfem +
                                                                      R"(block.msh"},
  {"mesh": ")" + polyfem + R"(floor_y.obj", "is_obstacle": true, "transformation": {"dimensions": [3, 3, 0]}}],
  "materials": [{"type": "NeoHookean", "E": 1e6, "nu": 0.4}], "time": {"dt": 0.01, "time_steps": 2},
  "contact": {"enabled": true, "dhat": 0.001}})");
  }
};

[[maybe_unused]] ::testing::Environment* const generated_inputs = ::testing::AddGlobalTestEnvironment(
    new GeneratedInputs);

class InputErrors : public ::testing::TestWithParam<std::tuple<BadInput, int>> {};

TEST_P(InputErrors, ExitOneWithAClearMessage) {
  const auto& [c, ranks] = GetParam();
  const Outcome o = run_dipc(c.scene, c.extra, ranks);
  EXPECT_EQ(o.status, 1) << o.output;
  EXPECT_NE(o.output.find("dipc: error: "), std::string::npos) << o.output;
  for (const auto& s : c.expected)
    EXPECT_NE(o.output.find(s), std::string::npos) << "missing '" << s << "' in:\n" << o.output;
  EXPECT_EQ(o.output.find("PETSC ERROR"), std::string::npos) << o.output;
}

INSTANTIATE_TEST_SUITE_P(
    Table, InputErrors,
    ::testing::Combine(
        ::testing::Values(
            BadInput{"bad_syntax", "bad_syntax.json", "", {"bad_syntax.json", "line 3"}},
            BadInput{"unknown_key", "unknown_key.json", "", {"unknown_key.json", "gravty"}},
            BadInput{"nu_half", "nu_half.json", "", {"nu_half.json", "materials[0].nu", "(-1, 0.5)"}},
            BadInput{"negative_dt", "negative_dt.json", "", {"negative_dt.json", "time.dt"}},
            BadInput{"inverted_mesh", "inverted_mesh.json", "", {"inverted.msh", "element 1", "inverted"}},
            BadInput{"nan_mesh", "nan_mesh.json", "", {"nan_coordinate.msh", "node 1"}},
            BadInput{"missing_mesh", "missing_mesh.json", "", {"missing.msh"}},
            BadInput{"inverted_hdf5_mesh", "inverted_hdf5_mesh.json", "", {"inverted_hex.h5", "element 1", "inverted"}},
            BadInput{"bad_topology_hdf5_mesh",
                     "bad_topology_mesh.json",
                     "",
                     {"bad_topology.h5", "/mesh/topology", "4 columns, expected 8"}},
            BadInput{
                "missing_hdf5_mesh", "missing_hdf5_mesh.json", "", {"missing_mesh.h5", "cannot open the mesh file"}},
            BadInput{"unknown_selection", "unknown_selection.json", "", {"unknown_selection.json", "cube.left"}},
            BadInput{"does_not_exist", "does_not_exist.json", "", {"does_not_exist.json"}},
            BadInput{"scene_is_a_directory", "", "", {"is a directory"}},
            BadInput{"msh_mesh_is_a_directory",
                     generated_dir + "directory_msh.json",
                     "",
                     {"directory_msh.json: geometry[0].mesh: ", "dir.msh: is a directory"}},
            BadInput{"hdf5_mesh_is_a_directory",
                     generated_dir + "directory_h5.json",
                     "",
                     {"directory_h5.json: geometry[0].mesh: ", "dir.h5: is a directory"}},
            BadInput{"obstacle_is_a_directory",
                     generated_dir + "directory_obj.json",
                     "",
                     {"directory_obj.json: contact.obstacles[0].mesh: ", "dir.obj: is a directory"}},
            BadInput{"nan_y_hdf5_mesh",
                     generated_dir + "nan_y_hdf5.json",
                     "",
                     {"nan_y.h5: node 2 has a non-finite y coordinate"}},
            BadInput{"huge_box",
                     generated_dir + "huge_box.json",
                     "",
                     {"huge_box.json: geometry[0].box.resolution [100000, 100000, 100000] gives 1000000000000000 "
                      "elements, needing about",
                      "GB available"}},
            BadInput{"polyfem_flattened_obstacle",
                     generated_dir + "polyfem_flattened_obstacle.json",
                     "",
                     {"polyfem_flattened_obstacle.json: geometry[1].transformation.dimensions: 0 along z, where the "
                      "mesh extends 0.5"}},
            BadInput{"big_box",
                     generated_dir + "big_box.json",
                     "",
                     {"big_box.json: geometry[0].box.resolution [1300, 1300, 1300] gives 2197000000 elements"}},
            BadInput{"huge_refine",
                     "small_box.json",
                     "-dipc_refine 100000",
                     {"box.resolution [2, 1, 1] x -dipc_refine 100000 gives 2000000000000000 elements"}},
            BadInput{"refine_overflows_int",
                     "small_box.json",
                     "-dipc_refine 2000000000",
                     {"x -dipc_refine 2000000000 gives more than 2147483647 elements along an axis"}},
            BadInput{"tiny_dt", generated_dir + "tiny_dt.json", "", {"tiny_dt.json: time.dt = 1e-300: below 1e-10 s"}},
            BadInput{"flat_box",
                     generated_dir + "flat_box.json",
                     "",
                     {"flat_box.json: geometry[0].box.size = [0.2,0.1,1e-30]: ", "are degenerate"}},
            BadInput{"intersecting_bodies",
                     "intersecting_bodies.json",
                     "",
                     {"not intersection-free", "crosses triangle", "\"upper\"", "\"lower\""}},
            BadInput{"touching_bodies",
                     "touching_bodies.json",
                     "",
                     {"not intersection-free", "touch", "\"upper\"", "\"lower\""}},
            BadInput{"nested_bodies", "nested_bodies.json", "", {"body \"inner\" lies inside body \"outer\""}},
            BadInput{"obstacle_missing",
                     "obstacle_missing.json",
                     "",
                     {"obstacle_missing.json", "contact.obstacles[0].mesh", "missing_floor.obj", "cannot open"}},
            BadInput{"obstacle_degenerate_face",
                     "obstacle_degenerate.json",
                     "",
                     {"contact.obstacles[0].mesh", "obstacle_degenerate.obj:10:", "degenerate triangle"}},
            BadInput{"obstacle_degenerate_stl_facet",
                     "obstacle_degenerate_stl.json",
                     "",
                     {"contact.obstacles[0].mesh", "obstacle_degenerate.stl: facet 1", "degenerate triangle"}},
            BadInput{"obstacle_nan",
                     "obstacle_nan.json",
                     "",
                     {"contact.obstacles[0].mesh", "obstacle_nan.obj:4:", "non-finite"}},
            BadInput{"obstacle_crossing",
                     "obstacle_crossing.json",
                     "",
                     {"not intersection-free", "crosses triangle", "of obstacle \"floor\" (",
                      "obstacle_floor.obj:", "\"cube\""}},
            BadInput{"negative_steps", "small_box.json", "-dipc_steps -1", {"-dipc_steps -1"}},
            BadInput{"zero_steps", "small_box.json", "-dipc_steps 0", {"-dipc_steps 0"}},
            BadInput{"non_numeric_steps", "small_box.json", "-dipc_steps abc", {"-dipc_steps abc", "not an integer"}},
            BadInput{"half_steps", "small_box.json", "-dipc_steps 2.5", {"-dipc_steps 2.5", "not an integer"}},
            BadInput{"steps_out_of_range",
                     "small_box.json",
                     "-dipc_steps 99999999999",
                     {"-dipc_steps 99999999999: out of range (at most 2147483647)"}},
            BadInput{"zero_refine", "small_box.json", "-dipc_refine 0", {"-dipc_refine 0"}},
            BadInput{"negative_velocity_tol", "small_box.json", "-dipc_velocity_tol -1", {"-dipc_velocity_tol -1"}},
            BadInput{
                "zero_velocity_tol_rel", "small_box.json", "-dipc_velocity_tol_rel 0", {"-dipc_velocity_tol_rel 0"}},
            BadInput{"nan_velocity_tol", "small_box.json", "-dipc_velocity_tol nan", {"-dipc_velocity_tol nan"}},
            BadInput{"negative_gpu_elements",
                     "small_box.json",
                     "-dipc_auto_gpu_elements -5",
                     {"-dipc_auto_gpu_elements -5"}},
            BadInput{
                "unknown_backend", "small_box.json", "-dipc_backend foo", {"-dipc_backend foo", "cpu, cuda, auto"}},
            BadInput{"unknown_preset",
                     "small_box.json",
                     "-dipc_preset quick",
                     {"-dipc_preset quick", "fast, balanced, accurate"}},
            BadInput{"non_boolean_flag", "small_box.json", "-dipc_pc_reuse abc", {"-dipc_pc_reuse abc"}},
            // Raised inside the solver setup as PETSC_ERR_USER_INPUT (app/petsc_input_errors.hpp).
            BadInput{"mixed_solve_without_mean_dilatation",
                     "small_box.json",
                     "-dipc_mixed_solve",
                     {"-dipc_mixed_solve needs mean-dilatation elements"}},
            // PETSc's own solver options, checked before the solvers read them (check_petsc_option_values).
            BadInput{"unknown_ksp_type",
                     "small_box.json",
                     "-ksp_type nonsense",
                     {"-ksp_type nonsense: not a KSP type of this PETSc"}},
            BadInput{"unknown_pc_type", "small_box.json", "-pc_type nonsense", {"-pc_type nonsense: not a PC type"}},
            BadInput{"non_numeric_ksp_rtol", "small_box.json", "-ksp_rtol abc", {"-ksp_rtol abc: not a number"}},
            BadInput{"ksp_rtol_above_one", "small_box.json", "-ksp_rtol 2", {"-ksp_rtol 2: must be in [0, 1)"}},
            BadInput{
                "negative_ksp_max_it", "small_box.json", "-ksp_max_it -3", {"-ksp_max_it -3: must be an integer >= 0"}},
            BadInput{"empty_output", "small_box.json", "-dipc_output", {"-dipc_output needs a value"}},
            BadInput{
                "unknown_option", "small_box.json", "-dipc_stepz 3", {"unknown option -dipc_stepz", "-dipc_steps?"}},
            BadInput{"misspelt_flag",
                     "small_box.json",
                     "-dipc_check_invariant",
                     {"unknown option -dipc_check_invariant ", "-dipc_check_invariants?"}},
            BadInput{"unknown_option_in_options_file",
                     "small_box.json",
                     "-options_file " + data_dir + "unknown_option.opts",
                     {"unknown option -dipc_stepz in options file ",
                      "unknown_option.opts (did you mean -dipc_steps?)"}},
            BadInput{"missing_options_file",
                     "small_box.json",
                     "-options_file " + data_dir + "none.opts",
                     {"-options_file", "none.opts: no such file"}},
            BadInput{"missing_nested_options_file",
                     "small_box.json",
                     "-options_file " + data_dir + "missing_nested.opts",
                     {"does_not_exist.opts (named in", "missing_nested.opts): no such file"}},
            BadInput{
                "zero_checkpoint_every", "small_box.json", "-dipc_checkpoint_every 0", {"-dipc_checkpoint_every 0"}},
            BadInput{"negative_checkpoint_minutes",
                     "small_box.json",
                     "-dipc_checkpoint_minutes -1",
                     {"-dipc_checkpoint_minutes -1", "must be > 0"}},
            BadInput{"missing_checkpoint",
                     "small_box.json",
                     "-dipc_restart " + bad_dir + "/none.h5",
                     {"none.h5", "does not exist"}},
            BadInput{"truncated_checkpoint",
                     "small_box.json",
                     "-dipc_restart " + bad_dir + "/truncated.h5",
                     {"truncated.h5", "is truncated"}},
            BadInput{"corrupt_checkpoint",
                     "small_box.json",
                     "-dipc_restart " + bad_dir + "/corrupt.h5",
                     {"corrupt.h5", "is corrupt", "/nodes/position", "checksum"}},
            BadInput{"foreign_hdf5_checkpoint",
                     "small_box.json",
                     "-dipc_restart " + bad_dir + "/foreign.h5",
                     {"foreign.h5", "not a dipc checkpoint"}},
            BadInput{"not_hdf5_checkpoint",
                     "small_box.json",
                     "-dipc_restart " + data_dir + "small_box.json",
                     {"small_box.json", "not an HDF5 file", "not a dipc checkpoint"}},
            BadInput{"mismatched_checkpoint",
                     "small_box.json",
                     "-dipc_refine 2 -dipc_restart " + good_checkpoint,
                     {"dipc.checkpoint.000001.h5", "another scene or mesh"}},
            // PolyFEM-format scenes with what dipc cannot model (issue 16 part 3).
            BadInput{"polyfem_bdf2",
                     "polyfem/refused_bdf2.json",
                     "",
                     {"refused_bdf2.json: time.integrator", "dipc cannot model this", "ImplicitEuler"}},
            BadInput{"polyfem_rotating_dirichlet",
                     "polyfem/refused_rotating_dirichlet.json",
                     "",
                     {"refused_rotating_dirichlet.json: boundary_conditions.dirichlet_boundary[0].value[0]",
                      "dipc cannot model this", "x, y or z"}}),
        ::testing::Values(1, 2)),
    [](const auto& info) {
      return std::string(std::get<0>(info.param).name) + "_np" + std::to_string(std::get<1>(info.param));
    });

// A PolyFEM-format scene runs, and rank 0 alone names each key dipc ignores, once.
TEST(InputErrors, PolyfemSceneNamesIgnoredKeys) {
  for (int ranks : {1, 2}) {
    const Outcome o = run_dipc("polyfem/drop_on_ground.json", "-dipc_steps 1", ranks);
    EXPECT_EQ(o.status, 0) << o.output;
    const std::string line = "dipc: PolyFEM scene: " + data_dir + "polyfem/drop_on_ground.json: solver.linear: ignored";
    const std::size_t at = o.output.find(line);
    EXPECT_NE(at, std::string::npos) << o.output;
    EXPECT_EQ(o.output.find(line, at + 1), std::string::npos) << "printed twice:\n" << o.output;
  }
}

// The good mesh runs the scene's 2 steps (time.steps) and writes them: one report line and one
// stats.csv row per step, and the XDMF named in the closing line.
TEST(InputErrors, GoodMeshRuns) {
  const std::string dir = "good_mesh_run";
  std::filesystem::remove_all(dir);
  const Outcome o = run_dipc("cube_good.json", "-dipc_quiet 0 -dipc_no_output 0 -dipc_output " + dir);
  ASSERT_EQ(o.status, 0) << o.output;
  for (const char* s :
       {"step     1  t 0.01 ", "step     2  t 0.02 ", "dipc: 2 steps written to good_mesh_run/dipc.xmf"})
    EXPECT_NE(o.output.find(s), std::string::npos) << "missing '" << s << "' in:\n" << o.output;
  EXPECT_EQ(o.output.find("step     3"), std::string::npos) << o.output;
  EXPECT_EQ(o.output.find("error"), std::string::npos) << o.output;
  std::ifstream stats(dir + "/stats.csv");
  std::vector<std::string> rows;
  for (std::string line; std::getline(stats, line);) rows.push_back(line);
  ASSERT_EQ(rows.size(), 3u) << "header and 2 steps expected in " << dir << "/stats.csv";
  EXPECT_EQ(rows[1].rfind("1,0.01,", 0), 0u) << rows[1];
  EXPECT_EQ(rows[2].rfind("2,0.02,", 0), 0u) << rows[2];
  EXPECT_TRUE(std::filesystem::exists(dir + "/dipc.xmf"));
}

// -options_file reaches PETSc: the shipped GAMG options replace the BoomerAMG default.
TEST(Options, OptionsFileIsRead) {
  const Outcome o = run_dipc("cube_good.json",
                             "-options_file " + dipc::test::source_dir() + "/scenes/solver/gamg.opts -snes_view");
  EXPECT_EQ(o.status, 0) << o.output;
  EXPECT_NE(o.output.find("type: gamg"), std::string::npos) << o.output;
  const Outcome d = run_dipc("cube_good.json", "-snes_view");
  EXPECT_NE(d.output.find("HYPRE BoomerAMG"), std::string::npos) << d.output;
}

// -dipc_preset: balanced without it; the named preset's options otherwise; and the user's own
// options, on the command line or in an -options_file, win over the preset's. Seen in the run
// header (the preset) and in -snes_view (the KSP's relative tolerance).
TEST(Options, PresetFillsInOnlyWhatTheUserLeftUnset) {
  struct Case {
    std::string extra, preset, ksp_rtol;
  };
  const std::string user_file = "-options_file " + data_dir + "ksp_rtol_1e-5.opts";
  for (const Case& c : {Case{"", "balanced", "relative=0.001,"}, Case{"-dipc_preset fast", "fast", "relative=0.001,"},
                        Case{"-dipc_preset accurate", "accurate", "relative=1e-08,"},
                        Case{"-dipc_preset fast -ksp_rtol 1e-6", "fast", "relative=1e-06,"},
                        Case{"-ksp_rtol 1e-6 -dipc_preset accurate", "accurate", "relative=1e-06,"},
                        Case{"-dipc_preset fast " + user_file, "fast", "relative=1e-05,"}}) {
    const Outcome o = run_dipc("cube_good.json", c.extra + " -snes_view");
    EXPECT_EQ(o.status, 0) << c.extra << "\n" << o.output;
    EXPECT_NE(o.output.find("solver preset " + c.preset + " "), std::string::npos) << c.extra << "\n" << o.output;
    EXPECT_NE(o.output.find("tolerances:  " + c.ksp_rtol), std::string::npos) << c.extra << "\n" << o.output;
  }
  // A fixed lag replaces the preconditioner reuse that balanced sets (the two are refused together).
  const Outcome lag = run_dipc("cube_good.json", "-snes_lag_preconditioner 2");
  EXPECT_EQ(lag.status, 0) << lag.output;
}

// A step that step recovery cannot take (no room to halve: -dipc_dt_min = dt, and a 100 m/s
// impact that Newton cannot resolve in one 5 ms step) stops the run with exit status 2 and a
// message naming the step, the time and the reason; the output written so far stays readable
// (the XDMF lists the initial state).
TEST(StepFailure, RecoveryThatRunsOutExitsWithStatusTwo) {
  for (int ranks : {1, 2}) {
    const std::string dir = "recovery_runs_out_np" + std::to_string(ranks);
    const std::string launcher = ranks > 1 ? std::string(DIPC_MPIEXEC) + " -n 2 " : "";
    const std::string cmd = launcher + DIPC_BINARY + " " + data_dir +
                            "impact_100ms.json -dipc_quiet -dipc_dt_min 0.005 "
                            "-dipc_output " +
                            dir + " 2>&1";
    FILE* pipe = popen(cmd.c_str(), "r");
    ASSERT_NE(pipe, nullptr);
    std::string output;
    std::array<char, 4096> buf;
    while (std::fgets(buf.data(), buf.size(), pipe)) output += buf.data();
    const int raw = pclose(pipe);
    ASSERT_TRUE(WIFEXITED(raw)) << output;
    EXPECT_EQ(WEXITSTATUS(raw), 2) << output;
    for (const char* s : {"dipc: error: step 1 (t = 0", "with dt = 0.005: ", "Newton failed",
                          "step recovery ran out (halving would go below -dipc_dt_min 0.005)"})
      EXPECT_NE(output.find(s), std::string::npos) << "missing '" << s << "' in:\n" << output;
    EXPECT_EQ(output.find("PETSC ERROR"), std::string::npos) << output;
    std::ifstream xmf(dir + "/impact.xmf");
    std::stringstream text;
    text << xmf.rdbuf();
    EXPECT_NE(text.str().find("<Time Value=\"0\""), std::string::npos) << dir << "/impact.xmf:\n" << text.str();
  }
}

}  // namespace
