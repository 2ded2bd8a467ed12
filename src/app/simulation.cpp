#include "app/simulation.hpp"

#include <petscversion.h>
#include <sys/resource.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "app/backend.hpp"
#include "app/gpu_aware_mpi.hpp"
#include "app/hypre_device_memory.hpp"
#include "app/checkpoint.hpp"
#include "app/library_exit.hpp"
#include "app/natural_order.hpp"
#include "app/openmp_threads.hpp"
#include "app/option_checks.hpp"
#include "app/output_obstacles.hpp"
#include "app/problem_builder.hpp"
#include "app/scene_slice.hpp"
#include "app/setup_heap.hpp"
#include "app/stop_signals.hpp"
#include "assembly/device_matrix.hpp"
#include "device/allocation_ledger.hpp"
#include "device/device_runtime.hpp"
#include "io/stats_csv.hpp"
#include "io/xdmf_writer.hpp"
#include "logging/log_stages.hpp"
#include "math/number_text.hpp"
#include "mesh/mesh_checks.hpp"
#include "nonlinear/step_recovery.hpp"
#include "nonlinear/time_integrator.hpp"
#include "partition/distributed_mesh.hpp"
#include "partition/mpi_exchange.hpp"

namespace dipc {

namespace {

// This process's peak resident memory so far (getrusage's ru_maxrss, KiB on Linux), in MiB.
double peak_rss_mib() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss / 1024.0;
}


// Output of one run: XDMF/HDF5 fields and stats.csv. Rows of the HDF5 file are in the input
// mesh's numbering (NaturalOrder), so the file is the same on any rank count and a restart on
// other ranks continues it. A restarted run (keep_steps >= 0) continues the files: the first
// keep_steps written steps and the stats rows up to keep_through_step stay, later ones (written
// after the checkpoint by the stopped run) are replaced.
class RunOutput {
 public:
  RunOutput(const Scene& scene, const std::string& dir, const DistributedMesh& mesh, NaturalOrder& order,
            const ProblemSetup& problem, const TimeIntegrator& integrator, long keep_steps = -1,
            long keep_through_step = -1)
      : mesh_(mesh),
        order_(order),
        contact_(integrator.contact() != nullptr),
        friction_(integrator.friction() != nullptr),
        dhat_(problem.contact_parameters.dhat),
        contact_parameters_(problem.contact_parameters) {
    std::vector<double> coords;
    for (int n = 0; n < mesh.num_owned_nodes; ++n)
      coords.insert(coords.end(), mesh.coordinates[n].begin(), mesh.coordinates[n].end());
    std::vector<double> block_coords;
    throw_on_petsc_error(order.nodes_to_blocks(coords.data(), &block_coords));
    // Element fields in the input numbering: the 8 input node ids of each element, its body
    // and its rank (ids below 2^53 pass through doubles exactly).
    const int ne = mesh.num_elements(), nb = order.num_elements();
    std::vector<std::int64_t> nodes(8 * static_cast<std::size_t>(nb));
    std::vector<double> local(ne), block;
    for (int corner = 0; corner < 8; ++corner) {
      for (int e = 0; e < ne; ++e) local[e] = static_cast<double>(mesh.node_input_id[mesh.elements[e][corner]]);
      throw_on_petsc_error(order.elements_to_blocks(local.data(), &block));
      for (int e = 0; e < nb; ++e)
        nodes[8 * static_cast<std::size_t>(e) + corner] = static_cast<std::int64_t>(block[e]);
    }
    std::vector<int> body(nb), rank(nb);
    for (int e = 0; e < ne; ++e) local[e] = mesh.element_body[e];
    throw_on_petsc_error(order.elements_to_blocks(local.data(), &block));
    for (int e = 0; e < nb; ++e) body[e] = static_cast<int>(block[e]);
    int my_rank;
    MPI_Comm_rank(mesh.comm, &my_rank);
    std::fill(local.begin(), local.end(), double(my_rank));
    throw_on_petsc_error(order.elements_to_blocks(local.data(), &block));
    for (int e = 0; e < nb; ++e) rank[e] = static_cast<int>(block[e]);
    // Selections in input node ids, each sorted over the ranks: every owned member goes to the
    // rank whose block of ids holds it, which writes the sorted ids it received as its rows.
    int num_ranks;
    MPI_Comm_size(mesh.comm, &num_ranks);
    std::vector<std::vector<std::int64_t>> selection_rows;
    std::vector<OutputMesh::Selection> selections;
    for (const auto& [name, members] : mesh.node_sets) {
      std::vector<std::vector<std::int64_t>> to_home(num_ranks);
      for (std::int32_t l : members)
        if (l < mesh.num_owned_nodes) {
          const std::int64_t id = mesh.node_input_id[l];
          to_home[block_of(id, mesh.num_global_nodes, num_ranks)].push_back(id);
        }
      selection_rows.push_back(exchange_records(to_home, mesh.comm));
      std::sort(selection_rows.back().begin(), selection_rows.back().end());
      OutputMesh::Selection set;
      set.name = name;
      set.count = static_cast<std::int64_t>(selection_rows.back().size());
      set.offset = exclusive_prefix(set.count, mesh.comm, &set.size);
      selections.push_back(set);
    }
    for (std::size_t k = 0; k < selections.size(); ++k) selections[k].ids = selection_rows[k].data();
    // Kinematic bodies (every node prescribed) as a cell flag, only when the scene has one.
    bool any_kinematic = false;
    for (const Body& b : scene.bodies) any_kinematic = any_kinematic || b.kinematic;
    std::vector<int> kinematic;
    if (any_kinematic) {
      for (int e = 0; e < ne; ++e) local[e] = scene.bodies[mesh.element_body[e]].kinematic ? 1.0 : 0.0;
      throw_on_petsc_error(order.elements_to_blocks(local.data(), &block));
      for (int e = 0; e < nb; ++e) kinematic.push_back(static_cast<int>(block[e]));
    }
    OutputMesh om;
    om.selections = selections;
    for (const Body& b : scene.bodies) om.body_names.push_back(b.name);
    om.element_kinematic = any_kinematic ? kinematic.data() : nullptr;
    om.contact_force = contact_;
    om.friction_force = friction_;
    if (contact_) {
      for (int k = 0; k < ContactForm::num_pair_kinds; ++k)
        om.contact_pair_kinds.push_back(ContactForm::pair_kind_name(k));
      om.obstacles = output_obstacles(contact_parameters_, scene_bounds(mesh, contact_parameters_));
    }
    om.comm = mesh.comm;
    om.num_global_nodes = mesh.num_global_nodes;
    om.node_offset = order.node_offset();
    om.num_owned_nodes = order.num_nodes();
    om.owned_coordinates = block_coords.data();
    om.num_global_elements = mesh.num_global_elements;
    om.element_offset = order.element_offset();
    om.num_elements = nb;
    om.element_nodes = nodes.data();
    om.element_body = body.data();
    om.element_rank = rank.data();
    writer_ = std::make_unique<XdmfWriter>(dir, scene.output_name, om, keep_steps);
    std::vector<std::string> columns{"step",
                                     "t",
                                     "dt",
                                     "substeps",
                                     "dt_cuts",
                                     "converged_by",
                                     "newton_its",
                                     "ksp_its",
                                     "alpha_min",
                                     "energy",
                                     "min_volume_ratio",
                                     "wall_s",
                                     "linear_solve_s",
                                     "kinetic_energy",
                                     "elastic_energy",
                                     "gravity_energy",
                                     "momentum_x",
                                     "momentum_y",
                                     "momentum_z",
                                     "angular_momentum_x",
                                     "angular_momentum_y",
                                     "angular_momentum_z"};
    if (contact_) {
      columns.push_back("contact_pairs");
      for (int k = 0; k < ContactForm::num_pair_kinds; ++k)
        columns.push_back(std::string("contact_pairs_") + ContactForm::pair_kind_name(k));
      columns.insert(columns.end(), {"min_distance", "min_distance_over_dhat", "kappa", "alpha_ccd", "broad_phase_s",
                                     "ccd_s", "barrier_s", "exchange_s"});
    }
    stats_ = std::make_unique<StatsCsv>(dir + "/stats.csv", columns, mesh.comm, keep_through_step);
  }

  PetscErrorCode write_fields(TimeIntegrator& integrator) {
    PetscFunctionBeginUser;
    StageScope stage(log_stages().output);
    Vec u;
    PetscCall(VecDuplicate(integrator.positions(), &u));
    PetscCall(VecWAXPY(u, -1.0, integrator.reference_positions(), integrator.positions()));
    const PetscScalar *ua, *va;
    std::vector<double> u_block, v_block, ratio_block;
    PetscCall(VecGetArrayRead(u, &ua));
    PetscCall(order_.nodes_to_blocks(ua, &u_block));
    PetscCall(VecRestoreArrayRead(u, &ua));
    PetscCall(VecGetArrayRead(integrator.velocities(), &va));
    PetscCall(order_.nodes_to_blocks(va, &v_block));
    PetscCall(VecRestoreArrayRead(integrator.velocities(), &va));
    std::vector<double> ratio;
    PetscCall(integrator.element_volume_ratios(&ratio));
    PetscCall(order_.elements_to_blocks(ratio.data(), &ratio_block));
    StepFields fields;
    fields.time = integrator.time();
    fields.displacement = u_block.data();
    fields.velocity = v_block.data();
    fields.volume_ratio = ratio_block.data();
    // Contact and friction forces (−∇B/h², −∇D/h²) and the active pairs, only with contact.
    std::vector<double> contact_block, friction_block;
    if (contact_) {
      Vec fc, ff = nullptr;
      PetscCall(VecDuplicate(u, &fc));
      if (friction_) PetscCall(VecDuplicate(u, &ff));
      std::array<long, ContactForm::num_pair_kinds> pairs{};
      PetscCall(integrator.contact_forces(fc, ff, &pairs));
      fields.contact_pairs.assign(pairs.begin(), pairs.end());
      for (auto [vec, out] : {std::pair{fc, &contact_block}, std::pair{ff, &friction_block}}) {
        if (!vec) continue;
        const PetscScalar* a;
        PetscCall(VecGetArrayRead(vec, &a));
        PetscCall(order_.nodes_to_blocks(a, out));
        PetscCall(VecRestoreArrayRead(vec, &a));
      }
      fields.contact_force = contact_block.data();
      fields.friction_force = friction_ ? friction_block.data() : nullptr;
      fields.obstacle_displacement = obstacle_displacements(contact_parameters_, integrator.time());
      PetscCall(VecDestroy(&fc));
      PetscCall(VecDestroy(&ff));
    }
    writer_->write_step(fields);
    library_exit::output_complete(writer_->xdmf_path(), writer_->num_steps_written());
    PetscCall(VecDestroy(&u));
    PetscFunctionReturn(0);
  }

  std::size_t steps_written() const { return writer_->num_steps_written(); }

  void write_stats(const StepReport& r, const PhysicalQuantities& q) {
    std::vector<StatsCsv::Cell> row{double(r.step),
                                    r.time,
                                    r.dt,
                                    double(r.substeps),
                                    double(r.dt_cuts),
                                    r.newton.ended_by,
                                    double(r.newton.iterations),
                                    double(r.newton.linear_iterations),
                                    r.newton.min_alpha,
                                    r.energy,
                                    r.min_volume_ratio,
                                    r.wall_seconds,
                                    r.linear_solve_seconds,
                                    q.kinetic_energy,
                                    q.elastic_energy,
                                    q.gravity_energy};
    for (double m : q.momentum) row.emplace_back(m);
    for (double l : q.angular_momentum) row.emplace_back(l);
    if (contact_) {
      row.emplace_back(double(r.contact_pairs));
      for (long n : r.contact_pairs_by_kind) row.emplace_back(double(n));
      row.insert(row.end(), {r.min_distance, r.min_distance / dhat_, r.kappa, r.alpha_ccd, r.broad_phase_seconds,
                             r.ccd_seconds, r.barrier_seconds, r.exchange_seconds});
    }
    stats_->row(row);
  }
  std::string xdmf_path() const { return writer_->xdmf_path(); }

 private:
  static void throw_on_petsc_error(PetscErrorCode code) {
    if (code) throw std::runtime_error("PETSc error " + std::to_string(code) + " while ordering the output");
  }

  // The bodies' and triangle-mesh obstacles' rest positions over all ranks (plane patches).
  static Bounds scene_bounds(const DistributedMesh& mesh, const ContactParameters& contact) {
    Bounds b{};
    const double inf = std::numeric_limits<double>::infinity();
    double lo[3] = {inf, inf, inf}, hi[3] = {-inf, -inf, -inf};
    const auto grow = [&](const double* x) {
      for (int c = 0; c < 3; ++c) lo[c] = std::min(lo[c], x[c]), hi[c] = std::max(hi[c], x[c]);
    };
    for (int n = 0; n < mesh.num_owned_nodes; ++n) grow(mesh.coordinates[n].data());
    for (const auto& o : contact.obstacles)
      for (const auto& X : o.rest) grow(X.data());
    MPI_Allreduce(MPI_IN_PLACE, lo, 3, MPI_DOUBLE, MPI_MIN, mesh.comm);
    MPI_Allreduce(MPI_IN_PLACE, hi, 3, MPI_DOUBLE, MPI_MAX, mesh.comm);
    for (int c = 0; c < 3; ++c) b[c] = lo[c], b[3 + c] = hi[c];
    return b;
  }

  const DistributedMesh& mesh_;
  NaturalOrder& order_;
  bool contact_, friction_;
  double dhat_;
  const ContactParameters& contact_parameters_;
  std::unique_ptr<XdmfWriter> writer_;
  std::unique_ptr<StatsCsv> stats_;
};

// Device memory around the integrator's setup, for the header's bytes-per-element line.
struct DeviceUse {
  bool matrix_on_device = false;
  std::size_t free_before = 0, free_after = 0;
};

PetscErrorCode print_header(MPI_Comm comm, const Scene& scene, const DistributedMesh& mesh, TimeIntegrator& integrator,
                            const RunOptions& options, double velocity_tol, double dt_min, const BackendChoice& backend,
                            const DeviceUse& device_use, const GpuAwareMpi& gpu_aware_mpi,
                            const std::string& hypre_memory, const OpenMpThreads& threads,
                            const HostThreads& host_threads) {
  PetscFunctionBeginUser;
  int size;
  MPI_Comm_size(comm, &size);
  int ne = mesh.num_elements(), ne_min, ne_max;
  MPI_Allreduce(&ne, &ne_min, 1, MPI_INT, MPI_MIN, comm);
  MPI_Allreduce(&ne, &ne_max, 1, MPI_INT, MPI_MAX, comm);
  VecType vtype;
  MatType mtype;
  PetscCall(VecGetType(integrator.positions(), &vtype));
  PetscCall(MatGetType(integrator.jacobian(), &mtype));
  std::string forms;
  for (const auto& f : integrator.form_names()) forms += (forms.empty() ? "" : ", ") + f;
  long long entries = integrator.hessian_entries(), total_entries = 0;
  MPI_Allreduce(&entries, &total_entries, 1, MPI_LONG_LONG, MPI_SUM, comm);
  PetscCall(PetscPrintf(comm, "dipc %s | PETSc %d.%d.%d | scene: %s\n", "0.1.0", PETSC_VERSION_MAJOR,
                        PETSC_VERSION_MINOR, PETSC_VERSION_SUBMINOR, scene.source.c_str()));
  const std::string per_rank_threads = !threads.available ? "library default (built without OpenMP)"
                                                          : std::to_string(threads.threads) +
                                                                (threads.from_environment ? " (OMP_NUM_THREADS)" : "");
  PetscCall(PetscPrintf(comm,
                        "  ranks %d | OpenMP threads per rank %s | setup threads %d (%s) | backend %s | "
                        "elements %lld (%d..%d per rank) | nodes %lld | dofs %d\n",
                        size, per_rank_threads.c_str(), host_threads.threads, host_threads.why.c_str(),
                        backend.description.c_str(), (long long)mesh.num_global_elements, ne_min, ne_max,
                        (long long)mesh.num_global_nodes, (int)integrator.num_dofs()));
  if (backend.space == MemorySpace::device) {
    // Measured on each rank as the drop in free device memory over the setup; the largest shown.
    double used = static_cast<double>(device_use.free_before) - static_cast<double>(device_use.free_after), max_used;
    MPI_Allreduce(&used, &max_used, 1, MPI_DOUBLE, MPI_MAX, comm);
    // Which device each rank took (node-local rank order): the first 16 ranks.
    std::vector<int> devices(size);
    MPI_Gather(&backend.device, 1, MPI_INT, devices.data(), 1, MPI_INT, 0, comm);
    std::string per_rank;
    for (int r = 0; r < std::min(size, 16); ++r) per_rank += (r ? "," : "") + std::to_string(devices[r]);
    if (size > 16) per_rank += ",…";
    PetscCall(PetscPrintf(comm,
                          "  GPU %s (devices by rank: %s) | setup used %.1f MiB on the fullest rank, %.0f B/element "
                          "(the bound dipc checks before the setup: %zu B/element%s)\n",
                          device::name(backend.device).c_str(), per_rank.c_str(), max_used / 1048576.0,
                          max_used / std::max(1, ne_max), device_bytes_per_element(device_use.matrix_on_device),
                          device_use.matrix_on_device ? " with the matrix and its copy for the preconditioner" : ""));
    // Where dipc's own share goes, on rank 0 (PETSc's vectors and matrix and hypre's hierarchy
    // are the rest of "setup used").
    PetscCall(PetscPrintf(comm, "  dipc's device arrays on rank 0 after the setup: %s\n",
                          device::allocation_ledger().per_element(static_cast<std::size_t>(ne), 6).c_str()));
    PetscCall(PetscPrintf(comm, "  MPI %s\n", gpu_aware_mpi.description.c_str()));
    if (!hypre_memory.empty()) PetscCall(PetscPrintf(comm, "  %s\n", hypre_memory.c_str()));
  }
  PetscCall(PetscPrintf(comm, "  Vec %s | Mat %s | COO entries %lld | forms: %s\n", vtype, mtype, total_entries,
                        forms.c_str()));
  PetscCall(
      PetscPrintf(comm,
                  "  %s, dt %g, %d steps, recovery down to dt %g | Newton: |p|_inf/h < %g, stalled below alpha %g\n",
                  scene.is_static ? "static" : "implicit Euler", scene.dt,
                  options.steps > 0 ? options.steps : scene.steps, dt_min, velocity_tol, options.alpha_floor));
  if (!options.preset.empty())
    PetscCall(PetscPrintf(comm, "  solver preset %s (-dipc_preset; options given explicitly win over it)\n",
                          options.preset.c_str()));
  if (options.check_invariants)
    PetscCall(PetscPrintf(comm, "  invariant checks on (-dipc_check_invariants): each step stops the run on an inverted "
                                "element%s\n",
                          scene.contact.enabled ? ", an edge-triangle crossing or a distance at or below zero" : ""));
  // The user's -snes_ options are honoured; -snes_rtol/atol/stol let PETSc's tests end a solve.
  std::string snes;
  for (const auto& o : integrator.user_snes_options()) snes += (snes.empty() ? "" : " ") + o;
  if (!snes.empty()) PetscCall(PetscPrintf(comm, "  user SNES options: %s\n", snes.c_str()));
  PetscFunctionReturn(0);
}

// The scene with every generated box's resolution multiplied by -dipc_refine.
Scene refined(const Scene& scene_in, int refine) {
  Scene scene = scene_in;
  for (Body& body : scene.bodies)
    if (body.box)
      for (int& r : body.box->resolution) r *= refine;
  return scene;
}

// What run_scene measures of its phases on this rank: wall times (s) and peak memory (MiB).
struct PhaseMeasures {
  double start = 0;  // MPI_Wtime at the run's start
  double partition = 0, setup = 0, output = 0;
  double rss_partition = 0, rss_setup = 0;  // peak resident memory after the partition, the setup
};

// The scene's mesh partitioned over the ranks, and what the partition phase learnt on the way.
struct PartitionedScene {
  DistributedMesh mesh;
  double diagonal = 0;            // of the input mesh's bounding box: the length scale
  std::uint64_t fingerprint = 0;  // of the scene and its mesh, for checkpoints
  Partitioner partitioner = Partitioner::metis;
  DistributeReport distribution;
  double slices_seconds = 0;  // building or reading the slices
};

// Mesh and partition: every rank builds or reads its slice of the input mesh, the slices are
// partitioned (METIS on rank 0 for meshes it can hold, PT-Scotch in parallel beyond) and each
// rank receives its part (partition/distributed_mesh.hpp: distribute_slices). `start` is the
// partition phase's start (MPI_Wtime).
PartitionedScene partition_scene(const Scene& scene, MPI_Comm comm, const RunOptions& options, double start) {
  StageScope stage(log_stages().partition);
  PartitionedScene p;
  MeshSlice slice = build_scene_slice(scene, comm);
  p.diagonal = slice_bounding_box_diagonal(slice);
  p.fingerprint = scene_fingerprint(scene, slice_digest(slice));
  p.partitioner = options.partitioner != "auto"                             ? parse_partitioner(options.partitioner)
                  : slice.num_global_elements <= options.metis_max_elements ? Partitioner::metis
                  : ptscotch_available()                                    ? Partitioner::ptscotch
                                                                            : Partitioner::rcb;
  p.slices_seconds = MPI_Wtime() - start;
  p.mesh = distribute_slices(slice, p.partitioner, scene.contact.enabled,
                             &p.distribution);  // the surface only for contact
  return p;
}

// The partition's quality and where the partition phase's time went (slowest rank per part).
PetscErrorCode print_partition(MPI_Comm comm, const PartitionedScene& partitioned) {
  PetscFunctionBeginUser;
  const DistributeReport& distribution = partitioned.distribution;
  double parts[7] = {partitioned.slices_seconds, distribution.match_faces, distribution.partition,
                     distribution.quality_check, distribution.elements,    distribution.nodes,
                     distribution.surface};
  MPI_Allreduce(MPI_IN_PLACE, parts, 7, MPI_DOUBLE, MPI_MAX, comm);
  const PartitionQuality& q = distribution.quality;
  PetscCall(PetscPrintf(comm,
                        "  partitioner %s | edge cut %lld of %lld interior faces | imbalance %.3f (parts %lld..%lld)\n",
                        partitioner_name(partitioned.partitioner), (long long)q.edge_cut, (long long)q.dual_edges,
                        q.imbalance, (long long)q.smallest_part, (long long)q.largest_part));
  PetscCall(PetscPrintf(comm,
                        "  partition phases (s): slices %.3f faces %.3f partitioner %.3f quality %.3f elements %.3f "
                        "nodes %.3f surface %.3f\n",
                        parts[0], parts[1], parts[2], parts[3], parts[4], parts[5], parts[6]));
  PetscFunctionReturn(0);
}

// Device memory before the setup, after checking that the setup will fit (device backend only).
DeviceUse device_use_before_setup(MPI_Comm comm, const BackendChoice& backend, int num_elements) {
  DeviceUse device_use;
  if (backend.space == MemorySpace::device) {
    device_use.matrix_on_device = device_matrix_requested();
    check_device_memory(comm, num_elements, device_use.matrix_on_device);
    device_use.free_before = device::memory_info().free_bytes;
  }
  return device_use;
}

// The shortest sub-step step recovery may take: -dipc_dt_min, by default the scene's dt / 1024.
double min_substep(const Scene& scene, const RunOptions& options) {
  const double dt_min = options.dt_min > 0 ? options.dt_min : scene.dt / 1024;
  if (dt_min > scene.dt)
    throw std::runtime_error("-dipc_dt_min " + format_number(dt_min) + " is larger than the scene's dt " +
                             format_number(scene.dt));
  return dt_min;
}

PetscErrorCode set_up_integrator(const DistributedMesh& mesh, const ProblemSetup& problem, const RunOptions& options,
                                 double velocity_tol, MemorySpace space, TimeIntegrator& integrator) {
  PetscFunctionBeginUser;
  StageScope stage(log_stages().setup);
  StepControl control;
  control.velocity_tol = velocity_tol;
  control.alpha_floor = options.alpha_floor;
  control.check_invariants = options.check_invariants;
  // A stop signal is agreed on at every Newton iteration as well as at step boundaries, so
  // that a long step does not outlast the grace time before SIGKILL (issue 32).
  control.stop_requested = [comm = mesh.comm] { return agree_on_signal(comm) != 0; };
  PetscCall(integrator.setup(mesh, problem, control, space));
  PetscFunctionReturn(0);
}

// What a checkpoint records of the run beside the state: the fingerprint, the scene, the options.
PetscErrorCode describe_run(const Scene& scene, std::uint64_t fingerprint, CheckpointRun* run) {
  PetscFunctionBeginUser;
  run->fingerprint = fingerprint;
  run->scene = scene.source;
  char* all = nullptr;
  PetscCall(PetscOptionsGetAll(nullptr, &all));
  run->options = all ? all : "";
  PetscCall(PetscFree(all));
  PetscFunctionReturn(0);
}

// Restart (-dipc_restart FILE | auto): the state, recovery's level and the output's extent from a
// checkpoint (*stored); *restarted stays false when auto finds none.
PetscErrorCode restart_from_checkpoint(MPI_Comm comm, const std::string& restart, const std::string& output_dir,
                                       const std::string& name, NaturalOrder& order, TimeIntegrator& integrator,
                                       StepRecovery& recovery, const CheckpointRun& run, CheckpointRun* stored,
                                       bool* restarted) {
  PetscFunctionBeginUser;
  const bool automatic = restart == "auto";
  const std::vector<std::string> candidates = automatic ? list_checkpoints(comm, output_dir, name)
                                                        : std::vector<std::string>{restart};
  if (candidates.empty())
    PetscCall(PetscPrintf(comm, "dipc: -dipc_restart auto: no checkpoint of \"%s\" in %s, starting from step 0\n",
                          name.c_str(), output_dir.c_str()));
  for (std::size_t i = 0; i < candidates.size() && !*restarted; ++i) {
    try {
      PetscCall(read_checkpoint(comm, candidates[i], order, integrator, recovery, run, stored));
      *restarted = true;
      PetscCall(PetscPrintf(comm, "dipc: restarting from %s: step %d, t %.10g\n", candidates[i].c_str(),
                            recovery.steps_taken(), integrator.time()));
    } catch (const CheckpointError& e) {
      // auto falls back on the older checkpoint when the newest is damaged; a checkpoint of
      // another scene, or a file the user named, is refused.
      if (!automatic || e.kind() == CheckpointError::Kind::mismatched || i + 1 == candidates.size()) throw;
      PetscCall(PetscPrintf(comm, "dipc: skipping %s, trying the one before\n", e.what()));
    }
  }
  PetscFunctionReturn(0);
}

// Checkpoints of the run's state between steps (collective): when one is due, and writing it.
class Checkpoints {
 public:
  Checkpoints(MPI_Comm comm, const RunOptions& options, const std::string& output_dir, const std::string& name,
              NaturalOrder& order, const TimeIntegrator& integrator, const StepRecovery& recovery, CheckpointRun& run,
              bool restarted)
      : comm_(comm),
        options_(options),
        output_dir_(output_dir),
        name_(name),
        order_(order),
        integrator_(integrator),
        recovery_(recovery),
        run_(run),
        last_step_(restarted ? recovery.steps_taken() : -1) {}

  // Step boundary: the ranks agree on a stop signal and on rank 0's wall-clock rule; a
  // checkpoint is due by either, every -dipc_checkpoint_every steps, and at the end.
  StopDecision decide_stop() const {
    const bool minutes_due = options_.checkpoint_minutes > 0 &&
                             MPI_Wtime() - last_wall_ >= 60 * options_.checkpoint_minutes;
    return agree_on_stop(comm_, minutes_due);
  }
  bool due(int s, const StopDecision& stop, bool at_end) const {
    const bool every_due = options_.checkpoint_every > 0 && s > 0 && s % options_.checkpoint_every == 0;
    // A stop writes one even when the run restarted from step s: its message names this file.
    return (stop.signal || stop.checkpoint_due || every_due || (at_end && checkpointing_)) &&
           (s != last_step_ || (stop.signal && !written_)) && !options_.setup_only;
  }

  // Collective: a checkpoint of the current state, whose output holds `output_steps` steps;
  // its time counts as output (*t_output).
  PetscErrorCode write(std::size_t output_steps, RunResult* result, double* t_output) {
    PetscFunctionBeginUser;
    const double t0 = MPI_Wtime();
    run_.output_steps = static_cast<long>(output_steps);
    result->checkpoint_path = checkpoint_path(output_dir_, name_, recovery_.steps_taken());
    PetscCall(write_checkpoint(comm_, result->checkpoint_path, order_, integrator_, recovery_, run_, name_));
    last_step_ = recovery_.steps_taken();
    written_ = true;
    last_wall_ = MPI_Wtime();
    result->checkpoint_seconds += last_wall_ - t0;
    *t_output += last_wall_ - t0;
    if (!options_.quiet) {
      std::error_code ec;
      const auto bytes = std::filesystem::file_size(result->checkpoint_path, ec);  // rank 0 prints
      PetscCall(PetscPrintf(comm_, "checkpoint: step %d written to %s (%.2f MB, %.3f s)\n", recovery_.steps_taken(),
                            result->checkpoint_path.c_str(), ec ? 0.0 : bytes / 1e6, last_wall_ - t0));
    }
    PetscFunctionReturn(0);
  }

  // Collective: after a stop request abandoned a step, the checkpoint of the current state (put
  // back to the last completed step), unless this run already wrote that step's.
  PetscErrorCode write_unless_current(std::size_t output_steps, RunResult* result, double* t_output) {
    PetscFunctionBeginUser;
    if (recovery_.steps_taken() != last_step_ || !written_) PetscCall(write(output_steps, result, t_output));
    PetscFunctionReturn(0);
  }

 private:
  MPI_Comm comm_;
  const RunOptions& options_;
  const std::string& output_dir_;
  const std::string& name_;
  NaturalOrder& order_;
  const TimeIntegrator& integrator_;
  const StepRecovery& recovery_;
  CheckpointRun& run_;
  const bool checkpointing_ = options_.checkpoint_every > 0 || options_.checkpoint_minutes > 0;
  double last_wall_ = MPI_Wtime();
  int last_step_;         // of the last checkpoint written or restarted from (-1: none)
  bool written_ = false;  // by this run
};

// A step's totals added to the run's.
void add_step_counts(const StepReport& r, RunResult* result) {
  result->newton_iterations += r.newton.iterations;
  result->max_contact_pairs = std::max(result->max_contact_pairs, r.contact_pairs);
  result->linear_iterations += r.newton.linear_iterations;
  result->preconditioner_rebuilds += r.newton.preconditioner_rebuilds;
  result->exact_hessian_iterations += r.newton.exact_hessian_iterations;
  result->exact_hessian_fallbacks += r.newton.exact_hessian_fallbacks;
  result->dt_cuts += r.dt_cuts;
}

// A step's line on the console.
PetscErrorCode print_step(MPI_Comm comm, const StepReport& r, const ProblemSetup& problem) {
  PetscFunctionBeginUser;
  std::string contact;
  if (problem.contact) {
    char buf[256];
    std::snprintf(buf, sizeof(buf), " | contacts %ld d_min %.3g (%.3g dhat) kappa %.3g alpha_ccd %.3g contact %.3f s",
                  r.contact_pairs, r.min_distance, r.min_distance / problem.contact_parameters.dhat, r.kappa,
                  r.alpha_ccd, r.broad_phase_seconds + r.ccd_seconds + r.barrier_seconds + r.exchange_seconds);
    contact = buf;
  }
  if (r.dirichlet_substeps)
    contact += "  (prescribed motion reached in " + std::to_string(r.dirichlet_substeps + 1) + " solves)";
  if (r.dt_cuts)
    contact += "  (" + std::to_string(r.substeps) + " sub-steps after " + std::to_string(r.dt_cuts) +
               " cut(s), smallest dt " + std::to_string(r.dt) + ")";
  PetscCall(
      PetscPrintf(comm,
                  "step %5d  t %-10.5g newton %3d (%s)  ksp %5d  alpha_min %-8.3g E %-14.8g J_min %-8.4g %.3f s%s\n",
                  r.step, r.time, (int)r.newton.iterations, r.newton.ended_by.c_str(), (int)r.newton.linear_iterations,
                  r.newton.min_alpha, r.energy, r.min_volume_ratio, r.wall_seconds, contact.c_str()));
  PetscFunctionReturn(0);
}

// The boundary before step s (collective): a stop signal and a checkpoint when one is due;
// *ends when the run ends here (its last step taken, or a stop signal). output_steps: the
// output's extent at this boundary, what a checkpoint of this step records.
PetscErrorCode step_boundary(int s, int steps, std::size_t output_steps, Checkpoints& checkpoints, RunResult* result,
                             double* t_output, bool* ends) {
  PetscFunctionBeginUser;
  const StopDecision stop = checkpoints.decide_stop();
  const bool at_end = s >= steps;
  if (checkpoints.due(s, stop, at_end)) PetscCall(checkpoints.write(output_steps, result, t_output));
  if (stop.signal) result->stop_signal = stop.signal;
  *ends = stop.signal || at_end;
  PetscFunctionReturn(0);
}


// Peak resident memory of each rank at the end of each phase (a high-water mark, so it never
// decreases): the largest and smallest rank.
PetscErrorCode print_peak_memory(MPI_Comm comm, const PhaseMeasures& measured) {
  PetscFunctionBeginUser;
  const double rss[3] = {measured.rss_partition, measured.rss_setup, peak_rss_mib()};
  double rss_max[3], rss_min[3];
  MPI_Allreduce(rss, rss_max, 3, MPI_DOUBLE, MPI_MAX, comm);
  MPI_Allreduce(rss, rss_min, 3, MPI_DOUBLE, MPI_MIN, comm);
  PetscCall(PetscPrintf(comm,
                        "peak host memory per rank (ru_maxrss, MiB, max/min over ranks): after partition %.1f/%.1f, "
                        "after setup %.1f/%.1f, at end %.1f/%.1f\n",
                        rss_max[0], rss_min[0], rss_max[1], rss_min[1], rss_max[2], rss_min[2]));
  PetscFunctionReturn(0);
}

// Timing table: per phase, the slowest rank's time. Every row is measured on each rank as a
// set of disjoint intervals (IncrementalPotential's timers), or is the remainder of an
// enclosing wall time after the disjoint intervals inside it, which cannot be negative: the
// Newton solves' remainder (KSP, AMG, vector work) and the run's (everything outside setup,
// solves and output: step bookkeeping, energies, checks, reports). Only the phases the run
// has are rows: no solve rows without a step, no contact row without contact, no "new
// matrix patterns" unless a pattern changed after setup, no output row without output.
PetscErrorCode report_phase_times(MPI_Comm comm, const RunOptions& options, const TimeIntegrator& integrator,
                                  const PhaseMeasures& measured, bool with_output, RunResult* result) {
  PetscFunctionBeginUser;
  const EvaluationTimes& ev = integrator.solve_evaluation_times();
  const bool contact_row = integrator.contact() != nullptr;
  const double assembly = ev.gradient + ev.hessian;
  // Without contact the segment hooks have no form work to do; what little they take is the
  // line search's.
  const double contact_work = ev.neighbourhood + ev.max_step;
  const double line_search = ev.energy + ev.validity + ev.segment + (contact_row ? 0.0 : contact_work);
  const double linear = integrator.solve_seconds() - evaluation_seconds(ev);
  const double total = MPI_Wtime() - measured.start;
  const double other = total - measured.partition - measured.setup - integrator.solve_seconds() - measured.output;
  enum Row {
    partition,
    setup,
    assembly_row,
    coo,
    line_search_row,
    contact,
    patterns,
    linear_row,
    output_row,
    other_row,
    total_row,
    rows
  };
  const double local[rows] = {
      measured.partition, measured.setup, assembly,        ev.coo_insert, line_search, contact_row ? contact_work : 0,
      ev.preallocation,   linear,         measured.output, other,         total};
  double worst[rows];
  MPI_Allreduce(local, worst, rows, MPI_DOUBLE, MPI_MAX, comm);
  PhaseTimes& pt = result->times;
  pt.partition = worst[partition], pt.setup = worst[setup], pt.assembly = worst[assembly_row];
  pt.coo_insert = worst[coo], pt.line_search = worst[line_search_row], pt.contact = worst[contact];
  pt.preallocation = worst[patterns], pt.linear_solve = worst[linear_row], pt.output = worst[output_row];
  pt.other = worst[other_row], pt.total = worst[total_row];
  result->new_matrix_patterns = ev.preallocations;  // the same on every rank (collective)
  result->pattern_remaps = ev.remaps;
  const bool solved = integrator.solve_seconds() > 0;
  const struct {
    Row row;
    const char* name;
    bool shown;
  } table[] = {{partition, "partition", true},
               {setup, "setup", true},
               {assembly_row, "assembly (gradient, Hessian)", solved},
               {coo, "  of which COO insertion", solved},
               {line_search_row, "line search (energy, validity, segments)", solved},
               {contact, "contact: ghost surfaces, broad phase, CCD", solved && contact_row},
               {patterns, "contact patterns: active sets, new matrices", solved && contact_row},
               {linear_row, "linear solve (KSP + AMG) and rest", solved},
               {output_row, "output", with_output},
               {other_row, "other (step reports, energies, checks)", true},
               {total_row, "total", true}};
  result->timing_rows.clear();
  for (const auto& r : table)
    if (r.shown) result->timing_rows.push_back(r.name);
  if (options.report) {
    PetscCall(PetscPrintf(comm, "\n%-42s %10s\n", "phase (max over ranks)", "seconds"));
    for (const auto& r : table)
      if (r.shown) PetscCall(PetscPrintf(comm, "%-42s %10.3f\n", r.name, worst[r.row]));
    if (ev.preallocations > 0 || ev.remaps > 0)
      PetscCall(PetscPrintf(comm,
                            "(%ld new matrix pattern(s) after setup, %ld active-set change(s) within the matrix)\n",
                            ev.preallocations, ev.remaps));
    PetscCall(print_peak_memory(comm, measured));
  }
  PetscFunctionReturn(0);
}


}  // namespace

PetscErrorCode gather_by_input_id(const DistributedMesh& mesh, Vec field, std::vector<double>* out) {
  PetscFunctionBeginUser;
  int rank, size;
  MPI_Comm_rank(mesh.comm, &rank);
  MPI_Comm_size(mesh.comm, &size);
  const PetscScalar* a;
  PetscCall(VecGetArrayRead(field, &a));
  std::vector<double> mine(a, a + 3 * mesh.num_owned_nodes);
  PetscCall(VecRestoreArrayRead(field, &a));
  std::vector<std::int64_t> ids(mesh.node_input_id.begin(), mesh.node_input_id.begin() + mesh.num_owned_nodes);
  int n = mesh.num_owned_nodes;
  std::vector<int> counts(size), displs(size);
  MPI_Gather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, mesh.comm);
  std::vector<std::int64_t> all_ids;
  std::vector<double> all_values;
  std::vector<int> counts3(size), displs3(size);
  if (rank == 0) {
    for (int r = 1; r < size; ++r) displs[r] = displs[r - 1] + counts[r - 1];
    for (int r = 0; r < size; ++r) counts3[r] = 3 * counts[r], displs3[r] = 3 * displs[r];
    all_ids.resize(mesh.num_global_nodes);
    all_values.resize(3 * mesh.num_global_nodes);
  }
  MPI_Gatherv(ids.data(), n, MPI_INT64_T, all_ids.data(), counts.data(), displs.data(), MPI_INT64_T, 0, mesh.comm);
  MPI_Gatherv(mine.data(), 3 * n, MPI_DOUBLE, all_values.data(), counts3.data(), displs3.data(), MPI_DOUBLE, 0,
              mesh.comm);
  if (rank == 0) {
    out->assign(3 * mesh.num_global_nodes, 0.0);
    for (std::size_t k = 0; k < all_ids.size(); ++k)
      for (int c = 0; c < 3; ++c) (*out)[3 * all_ids[k] + c] = all_values[3 * k + c];
  }
  PetscFunctionReturn(0);
}

// Everything a run holds from its setup to its end, in the order it is built (and destroyed in
// reverse: the output and checkpoints before the integrator they read, the mesh last).
struct Simulation::Impl {
  Scene scene;
  MPI_Comm comm;
  RunOptions options;
  PhaseMeasures measured;
  OpenMpThreads threads;
  PartitionedScene partitioned;
  ProblemSetup problem;
  std::unique_ptr<library_exit::ArmedRun> armed;
  TimeIntegrator integrator;
  std::unique_ptr<StepRecovery> recovery;
  std::string output_dir;
  NaturalOrder order;
  CheckpointRun run;
  std::unique_ptr<RunOutput> output;
  std::unique_ptr<Checkpoints> checkpoints;
  RunResult result;
  int steps = 0;  // the run's last step
  std::function<PetscErrorCode(const StepReport&)> on_substep;
  bool ended = false, finished = false;
};

Simulation::Simulation(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Simulation::~Simulation() = default;
bool Simulation::ended() const { return impl_->ended; }
const RunResult& Simulation::progress() const { return impl_->result; }
const Scene& Simulation::scene() const { return impl_->scene; }
int Simulation::steps_taken() const { return impl_->recovery->steps_taken(); }
int Simulation::last_step() const { return impl_->steps; }
TimeIntegrator& Simulation::integrator() { return impl_->integrator; }
const DistributedMesh& Simulation::mesh() const { return impl_->partitioned.mesh; }

PetscErrorCode Simulation::create(const Scene& scene_in, MPI_Comm comm, const RunOptions& options,
                                  std::unique_ptr<Simulation>* simulation) {
  PetscFunctionBeginUser;
  auto impl = std::make_unique<Impl>();
  Impl& m = *impl;
  m.scene = refined(scene_in, options.refine);
  m.comm = comm;
  m.options = options;
  const Scene& scene = m.scene;
  PhaseMeasures& measured = m.measured;
  RunResult* result = &m.result;
  measured.start = MPI_Wtime();
  m.threads = limit_openmp_threads();
  result->openmp_threads = m.threads.threads;
  const HostThreads host_threads = choose_host_threads(comm, options.host_threads, m.threads);
  const LogStages& stages = log_stages();  // registered first, in their order
  PetscBool device_types;
  PetscCall(default_types_for_device_hypre(&device_types));
  if (device_types)
    PetscCall(PetscPrintf(comm, "dipc: this PETSc's hypre runs on the GPU only, so BoomerAMG gets -vec_type cuda "
                                "-mat_type hypre (give -vec_type/-mat_type or another -pc_type to choose)\n"));

  auto setup_heap = std::make_unique<SetupHeap>();  // until the setup is done (app/setup_heap.hpp)
  measured.partition = MPI_Wtime();
  m.partitioned = partition_scene(scene, comm, options, measured.partition);
  const DistributedMesh& mesh = m.partitioned.mesh;
  check_file_elements(scene, mesh);
  measured.partition = MPI_Wtime() - measured.partition;
  measured.rss_partition = peak_rss_mib();

  // Setup: the problem, the backend and the integrator (forms, the first matrix, the solvers).
  measured.setup = MPI_Wtime();
  m.problem = build_problem(scene, mesh, m.partitioned.diagonal);
  double velocity_tol = 0;
  PetscCall(read_velocity_tol(comm, options, m.partitioned.diagonal, &velocity_tol));
  const BackendChoice backend = choose_backend(comm, options.backend, mesh.num_elements(),
                                               options.auto_gpu_min_elements);
  m.armed = std::make_unique<library_exit::ArmedRun>(
      mesh.num_elements(), backend.space == MemorySpace::device ? device::name(backend.device) : std::string());
  DeviceUse device_use = device_use_before_setup(comm, backend, mesh.num_elements());
  const double dt_min = min_substep(scene, options);
  PetscCall(set_up_integrator(mesh, m.problem, options, velocity_tol, backend.space, m.integrator));
  setup_heap.reset();
  m.recovery = std::make_unique<StepRecovery>(m.integrator, dt_min);
  if (backend.space == MemorySpace::device) device_use.free_after = device::memory_info().free_bytes;
  GpuAwareMpi gpu_aware_mpi;
  PetscCall(settle_gpu_aware_mpi(comm, backend.space == MemorySpace::device, &gpu_aware_mpi));
  std::string hypre_memory;
  PetscCall(use_block_cache_for_hypre(comm, backend.space == MemorySpace::device, &hypre_memory));
  measured.setup = MPI_Wtime() - measured.setup;
  measured.rss_setup = peak_rss_mib();
  // Everything that reads options (the solvers' setup included) has run: a -dipc_ option that
  // nothing read is misspelt or unknown, and would otherwise be ignored.
  check_no_unknown_options(comm);
  if (options.report) {
    PetscCall(print_header(comm, scene, mesh, m.integrator, options, velocity_tol, dt_min, backend, device_use,
                           gpu_aware_mpi, hypre_memory, m.threads, host_threads));
    PetscCall(print_partition(comm, m.partitioned));
  }

  m.output_dir = options.output_dir.empty() ? scene.output_directory : options.output_dir;
  PetscCall(m.order.setup(mesh));
  PetscCall(describe_run(scene, m.partitioned.fingerprint, &m.run));
  measured.output = MPI_Wtime();
  bool restarted = false;
  CheckpointRun stored;
  if (!options.restart.empty() && !options.setup_only)
    PetscCall(restart_from_checkpoint(comm, options.restart, m.output_dir, scene.output_name, m.order, m.integrator,
                                      *m.recovery, m.run, &stored, &restarted));
  if (options.write_output && !options.setup_only) {
    StageScope stage(stages.output);
    m.output = restarted ? std::make_unique<RunOutput>(scene, m.output_dir, mesh, m.order, m.problem, m.integrator,
                                                       stored.output_steps, m.recovery->steps_taken())
                         : std::make_unique<RunOutput>(scene, m.output_dir, mesh, m.order, m.problem, m.integrator);
    if (m.output->steps_written() == 0) PetscCall(m.output->write_fields(m.integrator));
    result->xdmf_path = m.output->xdmf_path();
  }
  measured.output = MPI_Wtime() - measured.output;
  m.checkpoints = std::make_unique<Checkpoints>(comm, m.options, m.output_dir, scene.output_name, m.order,
                                                m.integrator, *m.recovery, m.run, restarted);
  m.steps = options.setup_only ? 0 : options.steps > 0 ? options.steps : scene.steps;
  // Sub-steps of cut steps are written only when asked (-dipc_output_substeps).
  if (m.output && options.output_substeps)
    m.on_substep = [&m](const StepReport&) { return m.output->write_fields(m.integrator); };
  result->steps_taken = m.recovery->steps_taken();
  simulation->reset(new Simulation(std::move(impl)));
  PetscFunctionReturn(0);
}

PetscErrorCode Simulation::step(StepReport* report) {
  PetscFunctionBeginUser;
  Impl& m = *impl_;
  *report = StepReport{};
  if (m.ended) PetscFunctionReturn(0);
  const MPI_Comm comm = m.comm;
  RunResult* result = &m.result;
  StepRecovery& recovery = *m.recovery;
  const int s = recovery.steps_taken();
  // Also what the checkpoint records when this step is abandoned after writing sub-steps
  // (-dipc_output_substeps).
  const std::size_t output_steps = m.output ? m.output->steps_written() : 0;
  PetscCall(step_boundary(s, m.steps, output_steps, *m.checkpoints, result, &m.measured.output, &m.ended));
  if (m.ended) PetscFunctionReturn(0);
  library_exit::enter("step " + std::to_string(s + 1));
  StepReport& r = *report;
  PetscCall(recovery.step(&r, m.on_substep));
  add_step_counts(r, result);
  if (r.stopped) {
    // A stop signal came during the step: recovery put the state back to step s, whose
    // checkpoint is written now rather than after a step that may take minutes.
    result->stop_signal = agree_on_signal(comm);
    if (!m.options.quiet)
      PetscCall(PetscPrintf(comm,
                            "step %5d  abandoned after %d Newton iterations: signal %d; the state of step %d "
                            "is kept\n",
                            r.step, (int)r.newton.iterations, result->stop_signal, s));
    PetscCall(m.checkpoints->write_unless_current(output_steps, result, &m.measured.output));
    m.ended = true;
    PetscFunctionReturn(0);
  }
  if (!m.options.quiet)
    for (const std::string& cut : r.cuts)
      PetscCall(PetscPrintf(comm, "step %5d  failed attempt (%s)%s\n", r.step, cut.c_str(),
                            r.failure.empty() || &cut != &r.cuts.back() ? ": retrying with dt halved" : ""));
  if (!r.failure.empty()) {
    result->failure = "step " + std::to_string(r.step) + " (t = " + format_number(m.integrator.time()) +
                      " reached): " + r.failure;
    result->fatal = r.fatal;
    m.ended = true;
    PetscFunctionReturn(0);
  }
  result->steps_taken = recovery.steps_taken();
  PhysicalQuantities q;
  PetscCall(m.integrator.measure(&q));
  if (!m.options.quiet) PetscCall(print_step(comm, r, m.problem));
  if (m.output) {
    const double t0 = MPI_Wtime();
    m.output->write_stats(r, q);
    const int every = std::max(1, m.scene.output_every);
    if (r.step % every == 0 || s == m.steps - 1) PetscCall(m.output->write_fields(m.integrator));
    m.measured.output += MPI_Wtime() - t0;
  }
  PetscFunctionReturn(0);
}

PetscErrorCode Simulation::finish(RunResult* out) {
  PetscFunctionBeginUser;
  Impl& m = *impl_;
  PetscCheck(!m.finished, m.comm, PETSC_ERR_ARG_WRONGSTATE, "Simulation::finish: the run has already finished");
  RunResult* result = &m.result;
  // The last boundary, when the run ended before reaching it (its last step taken by step(),
  // or a caller that stops stepping early): the end's checkpoint.
  if (!m.ended) {
    const int s = m.recovery->steps_taken();
    bool ends = false;
    PetscCall(step_boundary(s, std::min(s, m.steps), m.output ? m.output->steps_written() : 0, *m.checkpoints, result,
                            &m.measured.output, &ends));
    m.ended = true;
  }
  m.finished = true;
  if (result->stop_signal) {
    // How long the stop took, for choosing the grace time before SIGKILL (jobs/README.md).
    const double since = seconds_since_stop_signal();
    MPI_Allreduce(&since, &result->stop_seconds, 1, MPI_DOUBLE, MPI_MAX, m.comm);
  }
  const DistributedMesh& mesh = m.partitioned.mesh;
  result->steps_taken = m.recovery->steps_taken();
  PetscCall(gather_by_input_id(mesh, m.integrator.positions(), &result->positions));
  PetscCall(gather_by_input_id(mesh, m.integrator.velocities(), &result->velocities));
  result->num_elements = mesh.num_global_elements;
  result->num_dofs = m.integrator.num_dofs();
  PetscCall(report_phase_times(m.comm, m.options, m.integrator, m.measured, m.output != nullptr, result));
  *out = *result;
  m.armed.reset();  // the run is over: a library's exit is no longer this run's
  PetscFunctionReturn(0);
}

PetscErrorCode run_scene(const Scene& scene, MPI_Comm comm, const RunOptions& options, RunResult* result) {
  PetscFunctionBeginUser;
  *result = RunResult{};
  std::unique_ptr<Simulation> simulation;
  PetscCall(Simulation::create(scene, comm, options, &simulation));
  while (!simulation->ended()) {
    StepReport report;
    PetscCall(simulation->step(&report));
  }
  PetscCall(simulation->finish(result));
  PetscFunctionReturn(0);
}

}  // namespace dipc
