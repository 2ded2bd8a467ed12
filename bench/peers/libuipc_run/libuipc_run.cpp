// libuipc_run: one of dipc's scenes in libuipc (github.com/spiriMirror/libuipc, the GPU IPC code
// issue 34 compares dipc with), from the job bench/peers/peer_job.py writes: the bodies as
// tetrahedra on dipc's nodes (bench/peers/hex_to_tets.py), stable neo-Hookean solids, implicit
// Euler (libuipc's bdf1), gravity, one ground plane, the barrier's d̂, friction and Newton's
// velocity tolerance as dipc has them. A kinematic body that is fixed has every node fixed; one
// that moves at a velocity follows X + v t through libuipc's soft position constraint (a
// penalty: libuipc has no exact prescribed motion for FEM nodes). Writes each frame's positions, body by body in the
// order of <body>.nodes.txt, as raw float64 (frame_<k>.bin, k = 0 the start) and one line per
// frame of wall-clock seconds (frames.csv); Newton iterations are read from libuipc's log.
//
//     libuipc_run JOB.json OUT_DIR [--backend NAME]
//
// The backend is libuipc's "cuda" unless given: "none", libuipc's backend that simulates nothing,
// checks the job's scene setup on a machine without a GPU.
// Not built with dipc: bench/peers/libuipc_run/CMakeLists.txt builds it against an existing
// libuipc build (bench/peers/README.md).
#include <uipc/constitution/soft_position_constraint.h>
#include <uipc/constitution/stable_neo_hookean.h>
#include <uipc/uipc.h>

#include <chrono>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace {

using namespace uipc;
using namespace uipc::core;
using namespace uipc::geometry;
using namespace uipc::constitution;

Vector3 vector3(const Json& j) { return Vector3{j.at(0).get<Float>(), j.at(1).get<Float>(), j.at(2).get<Float>()}; }

// The frame's positions of every body, in the job's body order, appended to one file.
void write_positions(const std::vector<S<GeometrySlot>>& slots, const std::filesystem::path& path) {
  const std::filesystem::path part = path.string() + ".part";
  {
    std::ofstream out(part, std::ios::binary);
    for (const auto& slot : slots) {
      auto positions = slot->geometry().as<SimplicialComplex>()->positions().view();
      for (const Vector3& x : positions) {
        const double xyz[3] = {x[0], x[1], x[2]};
        out.write(reinterpret_cast<const char*>(xyz), sizeof xyz);
      }
    }
    if (!out) throw std::runtime_error("cannot write " + part.string());
  }
  std::filesystem::rename(part, path);
}

int run(const std::filesystem::path& job_path, const std::filesystem::path& out_dir, const std::string& backend) {
  std::ifstream in(job_path);
  if (!in) throw std::runtime_error("cannot read " + job_path.string());
  const Json job = Json::parse(in);
  const std::filesystem::path job_dir = job_path.parent_path();
  std::filesystem::create_directories(out_dir);

  Engine engine{backend, (out_dir / "workspace").string()};
  World world{engine};
  Json config = Scene::default_config();
  config["dt"] = job.at("dt").get<Float>();
  config["gravity"] = vector3(job.at("gravity"));
  config["contact"]["enable"] = true;
  config["contact"]["d_hat"] = job.at("d_hat").get<Float>();
  const Float friction = job.at("friction").get<Float>();
  config["contact"]["friction"]["enable"] = friction > 0;
  config["contact"]["eps_velocity"] = job.at("eps_velocity").get<Float>();
  config["newton"]["velocity_tol"] = job.at("velocity_tol").get<Float>();
  config["newton"]["max_iter"] = job.value("newton_max_iter", 1024);
  config["linear_system"]["tol_rate"] = job.value("cg_tol_rate", 1e-3);
  Scene scene{config};
  scene.contact_tabular().default_model(friction, job.value("contact_resistance", 1e9));
  auto element = scene.contact_tabular().default_element();

  StableNeoHookean snh;
  SoftPositionConstraint soft_position;
  auto object = scene.objects().create("bodies");
  std::vector<S<GeometrySlot>> slots;
  for (const Json& body : job.at("bodies")) {
    const Json kinematic = body.value("kinematic", Json());
    SimplicialComplexIO io;
    SimplicialComplex mesh = io.read((job_dir / body.at("msh").get<std::string>()).string());
    label_surface(mesh);
    label_triangle_orient(mesh);
    // dipc's (lambda', mu') of the same stable neo-Hookean energy (peer_job.py).
    snh.apply_to(mesh, ElasticModuli::lame(body.at("lambda").get<Float>(), body.at("mu").get<Float>()),
                 body.at("rho").get<Float>());
    element.apply_to(mesh);
    const Vector3 v = vector3(body.at("velocity"));
    // The constitution made the attribute (zero); a mesh without it gets one.
    auto velocity = mesh.vertices().find<Vector3>(builtin::velocity);
    if (!velocity) velocity = mesh.vertices().create<Vector3>(builtin::velocity, Vector3::Zero());
    for (Vector3& vi : view(*velocity)) vi = v;
    const std::string motion = kinematic.is_object() ? kinematic.at("type").get<std::string>() : "";
    if (motion == "fixed") {
      for (IndexT& fixed : view(*mesh.vertices().find<IndexT>(builtin::is_fixed))) fixed = 1;
    } else if (motion == "velocity") {
      soft_position.apply_to(mesh, job.value("soft_position_strength", 100.0));
      // Its own object, so that its animation sees its geometry alone.
      auto moving = scene.objects().create(body.at("name").get<std::string>());
      slots.push_back(moving->geometries().create(mesh).geometry);
      const Vector3 velocity = vector3(kinematic.at("velocity"));
      scene.animator().insert(*moving, [velocity](Animation::UpdateInfo& info) {
        auto geo = info.geo_slots()[0]->geometry().as<SimplicialComplex>();
        auto rest = info.rest_geo_slots()[0]->geometry().as<SimplicialComplex>()->positions().view();
        auto constrained = view(*geo->vertices().find<IndexT>(builtin::is_constrained));
        auto aim = view(*geo->vertices().find<Vector3>(builtin::aim_position));
        const Float t = info.dt() * static_cast<Float>(info.frame());
        for (std::size_t i = 0; i < aim.size(); ++i) constrained[i] = 1, aim[i] = rest[i] + t * velocity;
      });
      continue;
    } else if (!motion.empty()) {
      throw std::runtime_error("body " + body.at("name").get<std::string>() + ": kinematic type " + motion +
                               " is not translated");
    }
    slots.push_back(object->geometries().create(mesh).geometry);
  }
  if (job.contains("ground"))
    object->geometries().create(ground(job["ground"].at("height").get<Float>(), vector3(job["ground"].at("normal"))));

  world.init(scene);
  if (!world.is_valid()) throw std::runtime_error("libuipc refused the scene (world.init)");
  write_positions(slots, out_dir / "frame_0.bin");
  std::ofstream frames(out_dir / "frames.csv");
  frames << "frame,wall_s\n";
  const int num_frames = job.at("frames").get<int>();
  for (int k = 1; k <= num_frames; ++k) {
    const auto start = std::chrono::steady_clock::now();
    world.advance();
    world.retrieve();
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (!world.is_valid()) throw std::runtime_error("libuipc stopped in frame " + std::to_string(k));
    write_positions(slots, out_dir / ("frame_" + std::to_string(k) + ".bin"));
    frames << k << ',' << seconds << '\n' << std::flush;
    std::fprintf(stderr, "libuipc_run: frame %d of %d, %.3f s\n", k, num_frames, seconds);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  const bool backend_given = argc == 5 && std::string(argv[3]) == "--backend";
  if (argc != 3 && !backend_given) {
    std::fprintf(stderr, "usage: libuipc_run JOB.json OUT_DIR [--backend NAME]\n");
    return 2;
  }
  try {
    return run(argv[1], argv[2], backend_given ? argv[4] : "cuda");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "libuipc_run: %s: %s\n", argv[1], e.what());
    return 1;
  }
}
