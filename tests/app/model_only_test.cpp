// "Model only what the scene requires" (issue 12): for scenes that each lack one feature —
// contact, friction, gravity, inertia (static) — inspects what was built: the forms, the COO
// entries against what the element and nodal terms alone need, no contact surface or contact
// form, no pattern-change, ghost-node or step-bound machinery, and, from a short run, the
// timing table's rows (only the phases the run has, none negative) and no new matrix pattern.
#include <gtest/gtest.h>

#include <set>
#include <string>
#include <vector>

#include "app/problem_builder.hpp"
#include "app/scene_mesh.hpp"
#include "app/simulation.hpp"
#include "mesh/mesh_checks.hpp"
#include "nonlinear/time_integrator.hpp"
#include "partition/distributed_mesh.hpp"

namespace dipc {
namespace {

// What setup built for a scene (global counts summed over the ranks).
struct Built {
  std::vector<std::string> forms;
  bool contact = false, friction = false;
  bool changing_pattern = false, extra_nodes = false, step_limit = false;
  long long coo_entries = 0;
  long long needed_entries = 0;  // elastic 576 per element + lumped inertia 3 per node + Dirichlet diagonal
  long long surface_triangles = 0, surface_vertices = 0;  // the mesh's contact surface
  bool masses = false;
  long patterns_at_setup = 0;
};

Built inspect(const Scene& scene) {
  int rank;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  HexMesh whole;
  double diagonal = 0;
  if (rank == 0) whole = build_scene_mesh(scene), diagonal = bounding_box_diagonal(whole);
  MPI_Bcast(&diagonal, 1, MPI_DOUBLE, 0, PETSC_COMM_WORLD);
  // As run_scene distributes it: the contact surface only with contact.
  const DistributedMesh mesh = distribute_mesh(whole, PETSC_COMM_WORLD, scene.contact.enabled);
  const ProblemSetup problem = build_problem(scene, mesh, diagonal);
  Built b;
  {
    TimeIntegrator integrator;
    StepControl control;
    control.velocity_tol = 1e-6;
    EXPECT_EQ(integrator.setup(mesh, problem, control), 0);
    b.forms = integrator.form_names();
    b.contact = integrator.contact() != nullptr;
    b.friction = integrator.friction() != nullptr;
    b.changing_pattern = integrator.has_changing_pattern();
    b.extra_nodes = integrator.has_extra_nodes();
    b.step_limit = integrator.has_step_limit();
    b.masses = !integrator.node_masses().empty();
    b.patterns_at_setup = integrator.evaluation_times().preallocations;
    long long local[2] = {integrator.hessian_entries(), 0}, total[2];
    // What the element and nodal terms need: 8×8 blocks of 3×3 per element, 3 diagonal
    // entries per owned node for a lumped mass, one diagonal entry per prescribed owned dof.
    local[1] = 576LL * mesh.num_elements() + (scene.is_static ? 0 : 3LL * mesh.num_owned_nodes);
    std::set<int> prescribed;
    for (const auto& set : problem.dirichlet)
      for (int n : set.local_nodes)
        if (n < mesh.num_owned_nodes) prescribed.insert(n);
    local[1] += 3LL * static_cast<long long>(prescribed.size());
    MPI_Allreduce(local, total, 2, MPI_LONG_LONG, MPI_SUM, PETSC_COMM_WORLD);
    b.coo_entries = total[0], b.needed_entries = total[1];
  }
  b.surface_triangles = mesh.owned_surface.num_global_triangles;
  b.surface_vertices = mesh.owned_surface.num_global_vertices;
  long long mine = static_cast<long long>(mesh.owned_surface.triangle_gid.size() + mesh.owned_surface.edges.size() +
                                          mesh.owned_surface.vertices.size() + mesh.boundary_face_mask.size());
  long long all = 0;
  MPI_Allreduce(&mine, &all, 1, MPI_LONG_LONG, MPI_SUM, PETSC_COMM_WORLD);
  if (!scene.contact.enabled) {
    EXPECT_EQ(all, 0) << "contact-surface data on a scene without contact";
  }
  return b;
}

RunResult run(const Scene& scene, int steps) {
  RunOptions o;
  o.steps = steps;
  o.write_output = false;
  o.quiet = true;
  o.report = false;
  RunResult r;
  EXPECT_EQ(run_scene(scene, PETSC_COMM_WORLD, o, &r), 0);
  EXPECT_TRUE(r.failure.empty()) << r.failure;
  return r;
}

bool has_row(const RunResult& r, const std::string& prefix) {
  for (const auto& row : r.timing_rows)
    if (row.rfind(prefix, 0) == 0) return true;
  return false;
}

// Every PhaseTimes entry is a time (none negative); the rows of a run without contact.
void expect_no_contact_phases(const RunResult& r) {
  const PhaseTimes& t = r.times;
  for (double v : {t.partition, t.setup, t.assembly, t.coo_insert, t.line_search, t.contact, t.preallocation,
                   t.linear_solve, t.output, t.other, t.total})
    EXPECT_GE(v, 0.0);
  EXPECT_EQ(t.contact, 0.0);
  EXPECT_EQ(t.preallocation, 0.0);
  EXPECT_EQ(r.new_matrix_patterns, 0);
  EXPECT_FALSE(has_row(r, "contact")) << "a contact row without contact";
  EXPECT_FALSE(has_row(r, "contact patterns"));
  EXPECT_FALSE(has_row(r, "output"));  // no output was written
  EXPECT_TRUE(has_row(r, "assembly"));
  EXPECT_TRUE(has_row(r, "linear solve"));
  EXPECT_TRUE(has_row(r, "total"));
  EXPECT_EQ(r.max_contact_pairs, 0);
}

void expect_no_contact_built(const Built& b) {
  EXPECT_FALSE(b.contact);
  EXPECT_FALSE(b.friction);
  EXPECT_FALSE(b.changing_pattern);
  EXPECT_FALSE(b.extra_nodes);
  EXPECT_FALSE(b.step_limit);
  EXPECT_EQ(b.surface_triangles, 0);
  EXPECT_EQ(b.surface_vertices, 0);
  EXPECT_EQ(b.coo_entries, b.needed_entries) << "COO entries beyond the element and nodal terms";
  EXPECT_EQ(b.patterns_at_setup, 1);
}

TEST(ModelOnly, NoContact) {
  const Scene scene = beam_scene();  // dynamic, gravity, clamped, no contact
  ASSERT_FALSE(scene.contact.enabled);
  const Built b = inspect(scene);
  EXPECT_EQ(b.forms, (std::vector<std::string>{"inertia (lumped)", "elastic", "body force"}));
  expect_no_contact_built(b);
  EXPECT_TRUE(b.masses);
  expect_no_contact_phases(run(scene, 3));
}

TEST(ModelOnly, NoGravity) {
  Scene scene = beam_scene();
  scene.gravity = {0, 0, 0};
  scene.bodies[0].initial_velocity = {0, 0, -0.1};  // something to solve for
  const Built b = inspect(scene);
  EXPECT_EQ(b.forms, (std::vector<std::string>{"inertia (lumped)", "elastic"}));
  expect_no_contact_built(b);
  expect_no_contact_phases(run(scene, 2));
}

TEST(ModelOnly, StaticHasNoInertia) {
  Scene scene = beam_scene();
  scene.is_static = true;
  const Built b = inspect(scene);
  EXPECT_EQ(b.forms, (std::vector<std::string>{"elastic", "body force"}));
  expect_no_contact_built(b);
  EXPECT_TRUE(b.masses);  // gravity needs them
  expect_no_contact_phases(run(scene, 1));

  // Static without gravity: nothing needs nodal masses.
  scene.gravity = {0, 0, 0};
  const Built bare = inspect(scene);
  EXPECT_EQ(bare.forms, (std::vector<std::string>{"elastic"}));
  EXPECT_FALSE(bare.masses);
  expect_no_contact_built(bare);
}

TEST(ModelOnly, ContactWithoutFriction) {
  Scene scene = default_scene();
  scene.contact.friction = 0;
  const Built b = inspect(scene);
  EXPECT_EQ(b.forms, (std::vector<std::string>{"inertia (lumped)", "elastic", "body force", "contact barrier"}));
  EXPECT_TRUE(b.contact);
  EXPECT_FALSE(b.friction);
  EXPECT_TRUE(b.changing_pattern && b.step_limit);
  // Ghost nodes are other ranks' nodes: one rank holds them all and has no ghost machinery.
  int size = 1;
  MPI_Comm_size(PETSC_COMM_WORLD, &size);
  EXPECT_EQ(b.extra_nodes, size > 1);
  EXPECT_GT(b.surface_triangles, 0);
  // The ground plane's vertex–plane pairs are in the pattern from the start.
  EXPECT_GT(b.coo_entries, b.needed_entries);
  // The contrast: contact scenes do get the contact row (a short run, before the impact).
  const RunResult r = run(scene, 2);
  EXPECT_TRUE(has_row(r, "contact"));
  for (double v : {r.times.assembly, r.times.line_search, r.times.contact, r.times.preallocation, r.times.linear_solve,
                   r.times.other})
    EXPECT_GE(v, 0.0);
  EXPECT_TRUE(has_row(r, "contact patterns"));
}

TEST(ModelOnly, FrictionOnlyWhenConfigured) {
  const Scene scene = default_scene();  // μ = 0.2
  const Built b = inspect(scene);
  EXPECT_TRUE(b.friction);
  EXPECT_EQ(b.forms.back(), "friction (lagged)");
}

}  // namespace
}  // namespace dipc
