// The contact barrier through the whole distributed path (ghost surfaces, extra nodes, COO
// across ranks) against finite differences on 1 and 2 ranks: two boxes (and a ground plane)
// closer than d̂, perturbed. With the Hessian projection switched off (when the form is built,
// or by set_exact_hessian) the Hessian must equal the differences of the gradient; with it on,
// it must be symmetric positive semi-definite. A
// body that meets only a plane keeps its first matrix pattern.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <random>

#include "contact_test_scene.hpp"
#include "forms/contact_form.hpp"
#include "mesh/box_generator.hpp"
#include "potential/incremental_potential.hpp"
#include "support/directional_difference.hpp"
#include "threads/host_threads.hpp"

namespace dipc {
namespace {

double hash_value(std::int64_t node, int c, int salt) {
  std::mt19937_64 rng(static_cast<std::uint64_t>(node * 3 + c) * 7919u + static_cast<std::uint64_t>(salt));
  return std::uniform_real_distribution<double>(-1.0, 1.0)(rng);
}

struct ContactFixture {
  DistributedMesh mesh;
  IncrementalPotential potential;
  ContactForm* contact = nullptr;
  Mat H = nullptr;

  ContactFixture(double gap, bool project, MPI_Comm comm = PETSC_COMM_WORLD) {
    mesh = distribute_mesh(slab_and_box(0.3 + gap), comm);
    ContactParameters params = slab_and_box_parameters();
    params.project_hessian = project;
    auto form = std::make_unique<ContactForm>(mesh, params);
    contact = form.get();
    std::vector<std::unique_ptr<Form>> forms;
    forms.push_back(std::move(form));
    EXPECT_EQ(potential.setup(mesh, std::move(forms), std::vector<char>(3 * mesh.num_local_nodes(), 0)), 0);
    EXPECT_EQ(potential.create_matrix(&H), 0);
  }
  ~ContactFixture() { MatDestroy(&H); }

  // x = X + 3e-3 · random, drawn per input node so all rank counts see the same state.
  void perturbed(Vec x, int salt, double amplitude) {
    PetscScalar* a;
    VecGetArray(x, &a);
    for (int n = 0; n < mesh.num_owned_nodes; ++n)
      for (int c = 0; c < 3; ++c)
        a[3 * n + c] = mesh.coordinates[n][c] + amplitude * hash_value(mesh.node_input_id[n], c, salt);
    VecRestoreArray(x, &a);
  }
};

// The exact Hessian either from a form built without projection or from one built with it and
// switched to exact by the potential (IncrementalPotential::set_exact_hessian, as Newton does).
class ContactFormExactHessian : public ::testing::TestWithParam<bool> {};

TEST_P(ContactFormExactHessian, GradientAndExactHessianMatchDifferences) {
  const bool switched = GetParam();
  ContactFixture f(0.005, /*project=*/switched);
  if (switched) {
    EXPECT_TRUE(f.potential.set_exact_hessian(true));
  }
  Vec x, d, w, zero;
  f.potential.create_global_vec(&x);
  for (Vec* v : {&d, &w, &zero}) VecDuplicate(x, v);
  f.perturbed(x, 1, 3e-3);
  VecZeroEntries(zero);
  f.perturbed(d, 2, 1.0);
  VecAXPY(d, -1.0, x);  // pure random direction
  VecAXPY(d, 1.0, x);
  {
    // d := random field (the X part cancels above only for readability); rebuild cleanly
    PetscScalar* a;
    VecGetArray(d, &a);
    for (int n = 0; n < f.mesh.num_owned_nodes; ++n)
      for (int c = 0; c < 3; ++c) a[3 * n + c] = hash_value(f.mesh.node_input_id[n], c, 3);
    VecRestoreArray(d, &a);
  }
  const double eps = 1e-7;
  // Candidates must cover the whole difference stencil x ± eps d.
  VecWAXPY(w, -eps, d, x);
  Vec twice;
  VecDuplicate(d, &twice);
  VecCopy(d, twice);
  VecScale(twice, 2 * eps);
  PetscReal alpha;
  ASSERT_EQ(f.potential.max_step(w, twice, &alpha), 0);

  PetscReal E0;
  f.potential.objective(x, &E0);
  EXPECT_GT(E0, 0) << "no pair is active: the test would be vacuous";
  test::DirectionalDifferences fd;
  ASSERT_EQ(test::directional_differences(f.potential, f.H, x, d, eps, &fd), 0);
  EXPECT_NEAR(fd.slope_fd, fd.slope, 1e-5 * std::abs(fd.slope));
  EXPECT_LT(fd.hessian_error, 1e-4 * fd.hessian_scale);
  VecDestroy(&twice);
  for (Vec* v : {&x, &d, &w, &zero}) VecDestroy(v);
}

INSTANTIATE_TEST_SUITE_P(ContactForm, ContactFormExactHessian, ::testing::Values(false, true),
                         [](const auto& info) { return info.param ? "switched_to_exact" : "built_without_projection"; });

TEST(ContactForm, ProjectedHessianIsSymmetricPositiveSemidefinite) {
  ContactFixture f(0.005, /*project=*/true);
  Vec x, d, Hd;
  f.potential.create_global_vec(&x);
  VecDuplicate(x, &d);
  VecDuplicate(x, &Hd);
  f.perturbed(x, 1, 3e-3);
  ASSERT_EQ(f.potential.prepare_point(x), 0);
  f.potential.hessian(x, f.H);
  PetscBool symmetric;
  MatIsSymmetric(f.H, 1e-12, &symmetric);
  EXPECT_TRUE(symmetric);
  for (int salt = 10; salt < 20; ++salt) {
    PetscScalar* a;
    VecGetArray(d, &a);
    for (int n = 0; n < f.mesh.num_owned_nodes; ++n)
      for (int c = 0; c < 3; ++c) a[3 * n + c] = hash_value(f.mesh.node_input_id[n], c, salt);
    VecRestoreArray(d, &a);
    MatMult(f.H, d, Hd);
    PetscReal q;
    VecDot(d, Hd, &q);
    EXPECT_GE(q, -1e-12) << "dᵀHd < 0";
  }
  VecDestroy(&x);
  VecDestroy(&d);
  VecDestroy(&Hd);
}

// A body that only meets a plane keeps its first matrix: vertex–plane pairs are in the pattern
// from the start (zeros while inactive), so bringing the box within d̂ of the plane turns its
// barrier on without a new pattern.
TEST(ContactForm, PlaneContactsKeepTheFirstPattern) {
  DistributedMesh mesh = distribute_mesh(generate_box({0.5, 0.5, 0.5}, {2, 2, 2}, {0, 0, 0.3}, 0, "box"),
                                         PETSC_COMM_WORLD);
  ContactParameters params;
  params.dhat = 0.02;
  params.kappa = 1.0;
  params.kappa_adaptive = false;
  params.planes.push_back({{0, 0, 0}, {0, 0, 1}});
  auto form = std::make_unique<ContactForm>(mesh, params);
  ContactForm* contact = form.get();
  std::vector<std::unique_ptr<Form>> forms;
  forms.push_back(std::move(form));
  IncrementalPotential potential;
  ASSERT_EQ(potential.setup(mesh, std::move(forms), std::vector<char>(3 * mesh.num_local_nodes(), 0)), 0);
  Mat H;
  ASSERT_EQ(potential.create_matrix(&H), 0);
  const long first = contact->pattern_version();
  Vec x;
  potential.create_global_vec(&x);
  PetscReal norms[2];
  for (int near = 0; near < 2; ++near) {
    // Far: the bottom face 0.3 above the plane; near: 0.01 above it, inside d̂.
    PetscScalar* a;
    VecGetArray(x, &a);
    for (int n = 0; n < mesh.num_owned_nodes; ++n)
      for (int c = 0; c < 3; ++c) a[3 * n + c] = mesh.coordinates[n][c] - (c == 2 && near ? 0.29 : 0.0);
    VecRestoreArray(x, &a);
    ASSERT_EQ(potential.prepare_point(x), 0);
    ASSERT_EQ(potential.hessian(x, H), 0);
    MatNorm(H, NORM_FROBENIUS, &norms[near]);
    EXPECT_EQ(contact->pattern_version(), first) << (near ? "near" : "far") << " the plane";
  }
  EXPECT_EQ(norms[0], 0.0) << "no pair is active far from the plane";
  EXPECT_GT(norms[1], 0.0) << "the plane's barrier is active near it";
  VecDestroy(&x);
  MatDestroy(&H);
}

// The same state gives the same energy and gradient norm on all ranks and on rank 0 alone.
// On one rank both runs would be the same run: the test needs several.
// The pair lists the device kernels read (candidates, and the Hessian pattern's active pairs)
// are built on the host threads, each pair in its own slot: the same lists on 1 and 4 threads,
// and the lists a serial pass over the set gives.
TEST(ContactForm, DevicePairListsAreTheSerialOnesOnAnyThreads) {
  ContactFixture f(0.0005, /*project=*/true);
  Vec x, zero;
  f.potential.create_global_vec(&x);
  VecDuplicate(x, &zero);
  f.perturbed(x, 5, 1e-4);
  VecZeroEntries(zero);
  PetscReal alpha = 0;
  ASSERT_EQ(f.potential.max_step(x, zero, &alpha), 0);  // the candidates at x
  PetscBool changed = PETSC_FALSE, remapped = PETSC_FALSE;
  ASSERT_EQ(f.potential.refresh_pattern(x, &changed, &remapped), 0);  // the active pairs at x

  const ContactSet& set = f.contact->set();
  const auto describe_into = [&](device::ContactPairList* list, const ContactSet::PairInfo& info) {
    list->add(info.kind, info.nodes.data(), info.weight, info.eps_x,
              info.plane ? static_cast<int>(info.plane - f.contact->parameters().planes.data()) : -1);
  };
  device::ContactPairList candidates, pattern;
  set.for_each_pair([&](CandidateKind kind, std::size_t i) {
    describe_into(&candidates, set.describe(kind, i));
    return true;
  });
  for (const auto& pe : set.pattern_pairs()) describe_into(&pattern, set.describe(pe.kind, pe.index));
  ASSERT_GT(candidates.size(), 0u);
  ASSERT_GT(pattern.size(), 0u);
  ASSERT_LT(pattern.size(), candidates.size());

  for (int threads : {1, 4}) {
    set_host_threads(threads, 1);
    EXPECT_TRUE(f.contact->candidate_pair_list() == candidates) << threads << " host threads";
    EXPECT_TRUE(f.contact->pattern_pair_list() == pattern) << threads << " host threads";
  }
  set_host_threads(1);
  VecDestroy(&x);
  VecDestroy(&zero);
}

TEST(ContactForm, SameEnergyAndGradientOnAnyRankCount) {
  double values[2][2];
  int rank, size;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  MPI_Comm_size(PETSC_COMM_WORLD, &size);
  if (size < 2) GTEST_SKIP() << "compares all ranks with rank 0 alone: needs at least 2 ranks";
  MPI_Comm self;
  MPI_Comm_split(PETSC_COMM_WORLD, rank == 0 ? 0 : MPI_UNDEFINED, 0, &self);
  for (int run = 0; run < 2; ++run) {
    if (run == 1 && rank != 0) break;
    ContactFixture f(0.004, true, run == 0 ? PETSC_COMM_WORLD : self);
    Vec x, g, p;
    f.potential.create_global_vec(&x);
    VecDuplicate(x, &g);
    VecDuplicate(x, &p);
    f.perturbed(x, 1, 3e-3);
    // A segment that sweeps the box down onto the slab, as in an impact step.
    PetscScalar* a;
    VecGetArray(p, &a);
    for (int n = 0; n < f.mesh.num_owned_nodes; ++n)
      for (int c = 0; c < 3; ++c) a[3 * n + c] = c == 2 && f.mesh.coordinates[n][2] > 0.29 ? -0.003 : 0.0;
    VecRestoreArray(p, &a);
    PetscReal alpha;
    ASSERT_EQ(f.potential.max_step(x, p, &alpha), 0);
    PetscReal E, gn;
    f.potential.objective(x, &E);
    f.potential.gradient(x, g);
    VecNorm(g, NORM_2, &gn);
    values[run][0] = E, values[run][1] = gn;
    VecDestroy(&x);
    VecDestroy(&g);
    VecDestroy(&p);
  }
  if (rank == 0) {
    EXPECT_GT(values[1][0], 0);
    EXPECT_NEAR(values[0][0], values[1][0], 1e-12 * values[1][0]);
    EXPECT_NEAR(values[0][1], values[1][1], 1e-12 * values[1][1]);
    MPI_Comm_free(&self);
  }
}

}  // namespace
}  // namespace dipc
