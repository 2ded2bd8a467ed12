// Checkpoints of a run (see checkpoint.hpp).
#include "app/checkpoint.hpp"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <regex>

#include "io/collective_error.hpp"

namespace dipc {

namespace {

// FNV-1a, 64 bits (Fowler, Noll, Vo): enough to tell scenes apart, not a cryptographic hash.
class Fnv1a {
 public:
  void bytes(const void* data, std::size_t n) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < n; ++i) hash_ = (hash_ ^ p[i]) * 0x100000001b3ULL;
  }
  template <class T>
  void value(const T& v) {
    bytes(&v, sizeof v);
  }
  void text(const std::string& s) {
    value(s.size());
    bytes(s.data(), s.size());
  }
  std::uint64_t hash() const { return hash_; }

 private:
  std::uint64_t hash_ = 0xcbf29ce484222325ULL;
};

std::string hex(std::uint64_t v) {
  char buf[24];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(v));
  return buf;
}

std::string file_prefix(const std::string& name) { return name + ".checkpoint."; }

}  // namespace

std::uint64_t scene_fingerprint(const Scene& scene, std::uint64_t mesh_digest) {
  Fnv1a h;
  h.value(mesh_digest);
  for (const Material& m : scene.materials) h.value(m.E), h.value(m.nu), h.value(m.rho), h.value(m.mean_dilatation);
  for (const Body& b : scene.bodies) {
    h.text(b.name);
    h.value(b.initial_velocity), h.value(b.initial_angular_velocity), h.value(b.spin_center);
    h.value(b.self_contact), h.value(b.kinematic);
  }
  h.value(scene.gravity);
  for (const DirichletCondition& d : scene.dirichlet) {
    h.text(d.selection.describe());
    h.value(d.kind), h.value(d.velocity), h.value(d.axis), h.value(d.center), h.value(d.angular_velocity);
  }
  h.value(scene.is_static), h.value(scene.dt), h.value(scene.lumped_mass);
  const ContactSettings& c = scene.contact;
  h.value(c.enabled), h.value(c.dhat), h.value(c.dhat_relative), h.value(c.kappa_adaptive), h.value(c.kappa);
  h.value(c.friction), h.value(c.epsv), h.value(c.friction_iterations);
  for (const Plane& p : c.planes) h.value(p.point), h.value(p.normal);
  return h.hash();
}

std::string checkpoint_path(const std::string& directory, const std::string& name, long step) {
  char number[32];
  std::snprintf(number, sizeof number, "%06ld", step);
  return (std::filesystem::path(directory.empty() ? "." : directory) / (file_prefix(name) + number + ".h5")).string();
}

std::vector<std::string> list_checkpoints(MPI_Comm comm, const std::string& directory, const std::string& name) {
  int rank;
  MPI_Comm_rank(comm, &rank);
  std::string joined;  // rank 0's list, one path a line
  if (rank == 0) {
    std::vector<std::pair<long, std::string>> found;
    const std::filesystem::path dir(directory.empty() ? "." : directory);
    std::error_code ec;
    const std::string prefix = file_prefix(name);
    for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) {
      const std::string file = entry.path().filename().string();
      if (file.rfind(prefix, 0) != 0 || file.size() <= prefix.size() + 3 || file.substr(file.size() - 3) != ".h5")
        continue;
      const std::string digits = file.substr(prefix.size(), file.size() - prefix.size() - 3);
      if (digits.empty() || digits.find_first_not_of("0123456789") != std::string::npos) continue;
      found.emplace_back(std::stol(digits), entry.path().string());
    }
    std::sort(found.begin(), found.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
    for (const auto& f : found) joined += f.second + "\n";
  }
  int length = static_cast<int>(joined.size());
  MPI_Bcast(&length, 1, MPI_INT, 0, comm);
  joined.resize(length);
  MPI_Bcast(joined.data(), length, MPI_CHAR, 0, comm);
  std::vector<std::string> paths;
  for (std::size_t start = 0, end; (end = joined.find('\n', start)) != std::string::npos; start = end + 1)
    paths.push_back(joined.substr(start, end - start));
  return paths;
}

PetscErrorCode write_checkpoint(MPI_Comm comm, const std::string& path, NaturalOrder& order,
                                const TimeIntegrator& integrator, const StepRecovery& recovery,
                                const CheckpointRun& run, const std::string& name, int keep) {
  PetscFunctionBeginUser;
  CheckpointContents c;
  PetscInt n;
  PetscCall(VecGetSize(integrator.positions(), &n));
  c.num_global_nodes = n / 3;
  c.node_offset = order.node_offset();
  c.num_block_nodes = order.num_nodes();
  const TimeIntegrator::ResumeState s = integrator.resume_state();
  std::vector<std::pair<const char*, Vec>> fields{{"position", integrator.positions()},
                                                  {"velocity", integrator.velocities()},
                                                  {"previous_position", integrator.previous_positions()}};
  if (s.friction_lagged) fields.emplace_back("friction_lag_position", integrator.friction_lag_positions());
  for (const auto& [field, vec] : fields) {
    const PetscScalar* a;
    PetscCall(VecGetArrayRead(vec, &a));
    PetscCall(order.nodes_to_blocks(a, &c.node_fields[field]));
    PetscCall(VecRestoreArrayRead(vec, &a));
  }
  const StepRecovery::State r = recovery.state();
  int size;
  MPI_Comm_size(comm, &size);
  c.integers = {{"step", r.steps_taken},
                {"recovery_level", r.level},
                {"recovery_successes_at_level", r.successes_at_level},
                {"output_steps", run.output_steps},
                {"friction_lagged", s.friction_lagged ? 1 : 0},
                {"ranks", size}};
  c.reals = {{"time", s.time},
             {"dt", integrator.scene_dt()},
             {"step_length", s.step_length},
             {"kappa", s.kappa},
             {"previous_min_distance2", s.previous_min_distance2}};
  c.texts = {{"scene_fingerprint", hex(run.fingerprint)}, {"options", run.options}, {"scene", run.scene}};
  int rank;
  MPI_Comm_rank(comm, &rank);
  std::string error;
  if (rank == 0) {
    std::error_code ec;
    const std::filesystem::path dir = std::filesystem::path(path).parent_path();
    if (!dir.empty()) std::filesystem::create_directories(dir, ec);
    if (ec) error = "cannot create the checkpoint directory '" + dir.string() + "': " + ec.message();
  }
  throw_if_failed_anywhere(comm, error);
  write_checkpoint_file(comm, path, c);

  // The newest `keep` stay, older ones go.
  const std::vector<std::string> all = list_checkpoints(comm, std::filesystem::path(path).parent_path().string(), name);
  if (rank == 0) {
    std::error_code ec;
    for (std::size_t i = static_cast<std::size_t>(keep); i < all.size(); ++i) std::filesystem::remove(all[i], ec);
  }
  PetscFunctionReturn(0);
}

PetscErrorCode read_checkpoint(MPI_Comm comm, const std::string& path, NaturalOrder& order, TimeIntegrator& integrator,
                               StepRecovery& recovery, const CheckpointRun& run, CheckpointRun* stored) {
  PetscFunctionBeginUser;
  CheckpointContents c;
  PetscInt n;
  PetscCall(VecGetSize(integrator.positions(), &n));
  c.num_global_nodes = n / 3;
  c.node_offset = order.node_offset();
  c.num_block_nodes = order.num_nodes();
  c.integers = {{"step", 0},
                {"recovery_level", 0},
                {"recovery_successes_at_level", 0},
                {"output_steps", 0},
                {"friction_lagged", 0}};
  c.reals = {{"time", 0}, {"dt", 0}, {"step_length", 0}, {"kappa", 0}, {"previous_min_distance2", 0}};
  c.texts = {{"scene_fingerprint", ""}, {"options", ""}, {"scene", ""}};
  // The fingerprint is checked before the node data: another scene is "mismatched", even when
  // it also has another node count.
  {
    CheckpointContents header;
    header.texts = {{"scene_fingerprint", ""}, {"scene", ""}};
    header.integers = {{"friction_lagged", 0}};
    read_checkpoint_file(comm, path, &header);
    c.node_fields = {{"position", {}}, {"velocity", {}}, {"previous_position", {}}};
    if (header.integers["friction_lagged"] && integrator.friction_lag_positions())
      c.node_fields["friction_lag_position"] = {};
    if (header.texts["scene_fingerprint"] != hex(run.fingerprint))
      throw CheckpointError(CheckpointError::Kind::mismatched,
                            "checkpoint '" + path + "' was written for another scene or mesh (" +
                                header.texts["scene"] + ", fingerprint " + header.texts["scene_fingerprint"] +
                                "; this run: " + run.scene + ", fingerprint " + hex(run.fingerprint) + ")");
  }
  read_checkpoint_file(comm, path, &c);
  for (const auto& [field, vec] : {std::pair<const char*, Vec>{"position", integrator.positions()},
                                   {"velocity", integrator.velocities()},
                                   {"previous_position", integrator.previous_positions()},
                                   {"friction_lag_position", integrator.friction_lag_positions()}}) {
    if (!c.node_fields.count(field)) continue;
    PetscScalar* a;
    PetscCall(VecGetArray(vec, &a));
    PetscCall(order.nodes_from_blocks(c.node_fields[field], a));
    PetscCall(VecRestoreArray(vec, &a));
  }
  TimeIntegrator::ResumeState s;
  s.time = c.reals["time"];
  s.step_length = c.reals["step_length"];
  s.kappa = c.reals["kappa"];
  s.previous_min_distance2 = c.reals["previous_min_distance2"];
  s.friction_lagged = c.node_fields.count("friction_lag_position") > 0;
  PetscCall(integrator.resume(s));
  StepRecovery::State r;
  r.steps_taken = static_cast<int>(c.integers["step"]);
  r.level = static_cast<int>(c.integers["recovery_level"]);
  r.successes_at_level = static_cast<int>(c.integers["recovery_successes_at_level"]);
  recovery.resume(r);
  stored->fingerprint = run.fingerprint;
  stored->output_steps = static_cast<long>(c.integers["output_steps"]);
  stored->options = c.texts["options"];
  stored->scene = c.texts["scene"];
  PetscFunctionReturn(0);
}

}  // namespace dipc
