// The assembled incremental potential on 1 and 2 ranks against finite differences: energy →
// gradient (directional derivative) and gradient → Hessian (MatMult), through the whole
// distributed path — ghost gathering, reverse scatter of ghost gradients, COO assembly across
// ranks and Dirichlet elimination — for both lumped and consistent inertia, elasticity and
// gravity. At rest the neo-Hookean tangent has zero (rotation) modes that any perturbation can
// make slightly negative, which the PSD projection then clamps; under a 5 % uniform expansion
// every mode is positive (|λ ln J − μ| < μ σᵢσⱼ), so the projection is the identity there and
// the comparison is exact up to the difference error. The same for stable neo-Hookean
// elements (materials.hpp), whose tangent is positive definite there too.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <tuple>

#include "forms/body_force_form.hpp"
#include "forms/elastic_form.hpp"
#include "forms/inertia_form.hpp"
#include "mesh/box_generator.hpp"
#include "potential/incremental_potential.hpp"
#include "support/directional_difference.hpp"
#include "threads/host_threads.hpp"

namespace dipc {
namespace {

// Deterministic pseudo-random value per (global node, component, salt), equal on every rank.
double hash_value(std::int64_t node, int c, int salt) {
  std::mt19937_64 rng(static_cast<std::uint64_t>(node * 3 + c) * 7919u + static_cast<std::uint64_t>(salt));
  return std::uniform_real_distribution<double>(-1.0, 1.0)(rng);
}

class PotentialFiniteDifferences : public ::testing::TestWithParam<std::tuple<bool, MaterialModel>> {};

TEST_P(PotentialFiniteDifferences, GradientAndHessianMatchDifferences) {
  const bool lumped = std::get<0>(GetParam());
  MPI_Comm comm = PETSC_COMM_WORLD;
  HexMesh whole = generate_box({2, 1, 1}, {4, 2, 2}, {0, 0, 0}, 0, "box");
  DistributedMesh mesh = distribute_mesh(whole, comm);
  const double h = 0.01;
  BodyMaterial material{/*lambda*/ 4e5, /*mu*/ 3e5, /*rho*/ 900};
  material.model = std::get<1>(GetParam());
  ElementData elements(mesh, {material});
  GhostExchange exchange;
  ASSERT_EQ(exchange.setup(mesh, 3), 0);

  // Complete lumped masses on local nodes (what TimeIntegrator assembles), from the element
  // loop plus a scalar ghost exchange.
  GhostExchange scalar;
  ASSERT_EQ(scalar.setup(mesh, 1), 0);
  Vec ml, mg;
  scalar.create_local_vec(&ml);
  scalar.create_global_vec(&mg);
  VecZeroEntries(ml);
  VecZeroEntries(mg);
  PetscScalar* m;
  VecGetArray(ml, &m);
  lumped_mass(elements.block(), elements.rho.data(), m);
  VecRestoreArray(ml, &m);
  scalar.add_to_global(ml, mg);
  scalar.to_local(mg, ml);
  const PetscScalar* mc;
  VecGetArrayRead(ml, &mc);
  std::vector<double> node_mass(mc, mc + mesh.num_local_nodes());
  VecRestoreArrayRead(ml, &mc);
  VecDestroy(&ml);
  VecDestroy(&mg);

  std::vector<std::unique_ptr<Form>> forms;
  if (lumped)
    forms.push_back(std::make_unique<LumpedInertiaForm>(node_mass, mesh.num_owned_nodes, mesh.node_offset));
  else
    forms.push_back(std::make_unique<ConsistentInertiaForm>(elements));
  forms.push_back(std::make_unique<ElasticForm>(elements, h * h));
  forms.push_back(
      std::make_unique<BodyForceForm>(node_mass, mesh.num_owned_nodes, std::array<double, 3>{0, -3, -9.81}, h * h));
  std::vector<char> prescribed(3 * mesh.num_local_nodes(), 0);
  for (std::int32_t n : mesh.node_sets.at("box.xmin"))
    prescribed[3 * n] = prescribed[3 * n + 1] = prescribed[3 * n + 2] = 1;
  IncrementalPotential potential;
  ASSERT_EQ(potential.setup(mesh, std::move(forms), prescribed), 0);
  Mat H;
  ASSERT_EQ(potential.create_matrix(&H), 0);

  // x = 1.05 X + small perturbation, x̂ = X + another, direction d zero at Dirichlet dofs.
  Vec x, xhat, d;
  exchange.create_global_vec(&x);
  for (Vec* v : {&xhat, &d}) VecDuplicate(x, v);
  PetscScalar *xa, *xh, *da;
  VecGetArray(x, &xa);
  VecGetArray(xhat, &xh);
  VecGetArray(d, &da);
  for (int n = 0; n < mesh.num_owned_nodes; ++n)
    for (int c = 0; c < 3; ++c) {
      const std::int64_t id = mesh.node_input_id[n];
      xa[3 * n + c] = 1.05 * mesh.coordinates[n][c] + 0.002 * hash_value(id, c, 1);
      xh[3 * n + c] = mesh.coordinates[n][c] + 0.02 * hash_value(id, c, 2);
      da[3 * n + c] = prescribed[3 * n + c] ? 0.0 : hash_value(id, c, 3);
    }
  VecRestoreArray(x, &xa);
  VecRestoreArray(xhat, &xh);
  VecRestoreArray(d, &da);
  ASSERT_EQ(potential.begin_step(xhat), 0);

  // Energy -> gradient, gradient -> Hessian, along d.
  test::DirectionalDifferences fd;
  ASSERT_EQ(test::directional_differences(potential, H, x, d, 1e-6, &fd), 0);
  EXPECT_NEAR(fd.slope_fd, fd.slope, 1e-6 * std::abs(fd.slope)) << "directional derivative";
  EXPECT_GT(std::abs(fd.slope), 1e-8);
  EXPECT_LT(fd.hessian_error, 1e-6 * fd.hessian_scale) << "Hessian-vector product vs differences of the gradient";

  // The Hessian is symmetric (eliminated Dirichlet rows and columns included).
  PetscBool symmetric;
  MatIsSymmetric(H, 1e-10, &symmetric);
  EXPECT_TRUE(symmetric);

  MatDestroy(&H);
  for (Vec* v : {&x, &xhat, &d}) VecDestroy(v);
}

INSTANTIATE_TEST_SUITE_P(InertiaAndMaterial, PotentialFiniteDifferences,
                         ::testing::Combine(::testing::Values(true, false),
                                            ::testing::Values(MaterialModel::neo_hookean,
                                                              MaterialModel::stable_neo_hookean)),
                         [](const auto& info) {
                           return std::string(std::get<0>(info.param) ? "lumped_" : "consistent_") +
                                  material_model_name(std::get<1>(info.param));
                         });

// The step report's J_min (IncrementalPotential::min_volume_ratio): the elements' form gives the
// smallest volume ratio of its elements, on 1 and 4 host threads alike and equal to the element
// loop's own pass over the local elements, reduced over the ranks; without an element form
// there is none to give.
TEST(PotentialMinVolumeRatio, TheElementFormGivesTheElementPassesMinimumOnAnyThreads) {
  MPI_Comm comm = PETSC_COMM_WORLD;
  HexMesh whole = generate_box({2, 1, 1}, {8, 4, 4}, {0, 0, 0}, 0, "box");
  DistributedMesh mesh = distribute_mesh(whole, comm);
  ElementData elements(mesh, {BodyMaterial{4e5, 3e5, 900}});
  std::vector<std::unique_ptr<Form>> forms;
  forms.push_back(std::make_unique<ElasticForm>(elements, 1e-4));
  IncrementalPotential potential;
  ASSERT_EQ(potential.setup(mesh, std::move(forms), std::vector<char>(3 * mesh.num_local_nodes(), 0)), 0);
  GhostExchange exchange;
  ASSERT_EQ(exchange.setup(mesh, 3), 0);
  Vec x, xl;
  exchange.create_global_vec(&x);
  exchange.create_local_vec(&xl);
  PetscScalar* xa;
  VecGetArray(x, &xa);
  for (int n = 0; n < mesh.num_owned_nodes; ++n)
    for (int c = 0; c < 3; ++c)
      xa[3 * n + c] = (1.0 - 0.05 * c) * mesh.coordinates[n][c] + 0.01 * hash_value(mesh.node_input_id[n], c, 4);
  VecRestoreArray(x, &xa);
  exchange.to_local(x, xl);
  const PetscScalar* xla;
  VecGetArrayRead(xl, &xla);
  const double local = min_volume_ratio(elements.block(), xla, nullptr);
  VecRestoreArrayRead(xl, &xla);
  double expected = 0;
  MPI_Allreduce(&local, &expected, 1, MPI_DOUBLE, MPI_MIN, comm);
  ASSERT_GT(expected, 0.0);
  ASSERT_LT(expected, 1.0);

  for (int threads : {1, 4}) {
    set_host_threads(threads, 1);
    double ratio = 0;
    bool found = false;
    ASSERT_EQ(potential.min_volume_ratio(x, &ratio, &found), 0);
    EXPECT_TRUE(found);
    EXPECT_EQ(ratio, expected) << threads << " host threads";
  }
  set_host_threads(1);

  std::vector<double> node_mass(mesh.num_local_nodes(), 1.0);
  std::vector<std::unique_ptr<Form>> inertia_only;
  inertia_only.push_back(std::make_unique<LumpedInertiaForm>(node_mass, mesh.num_owned_nodes, mesh.node_offset));
  IncrementalPotential no_elements;
  ASSERT_EQ(no_elements.setup(mesh, std::move(inertia_only), std::vector<char>(3 * mesh.num_local_nodes(), 0)), 0);
  double ratio = 0;
  bool found = true;
  ASSERT_EQ(no_elements.min_volume_ratio(x, &ratio, &found), 0);
  EXPECT_FALSE(found);
  VecDestroy(&x);
  VecDestroy(&xl);
}

// The mean-dilatation element is neo-Hookean only: a body asking for it with another model is
// refused where the element data are built (the scene parser refuses it earlier).
TEST(ElementData, RefusesMeanDilatationWithStableNeoHookean) {
  HexMesh whole = generate_box({1, 1, 1}, {2, 2, 2}, {0, 0, 0}, 0, "box");
  DistributedMesh mesh = distribute_mesh(whole, PETSC_COMM_WORLD);
  BodyMaterial material{4e5, 3e5, 900};
  material.volumetric = VolumetricTerm::mean_dilatation;
  material.model = MaterialModel::stable_neo_hookean;
  if (mesh.num_elements() == 0) GTEST_SKIP() << "no element on this rank";
  try {
    ElementData elements(mesh, {material});
    FAIL() << "accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("neo-Hookean only, not stable_neo_hookean"), std::string::npos) << e.what();
  }
  material.model = MaterialModel::neo_hookean;
  EXPECT_NO_THROW(ElementData(mesh, {material}));
}

}  // namespace
}  // namespace dipc
