// The mixed u-p linear solve (mixed_linear_solve.hpp) against the primal Newton system, through
// the whole distributed path (ghosts, COO assembly, Dirichlet elimination), on mean-dilatation
// elements at nu = 0.4999 and nu = 0 (d_e = 0: the s block must vanish, not blow up):
//  - the split Hessian A + Bsᵀ Bs (VolumetricSplit::split_volumetric(), the shell product)
//    equals the assembled full Hessian H of the same forms unsplit, applied to a random vector;
//  - the mixed solve's du equals the primal solve's du = H⁻¹ r (CG on the assembled H, tight
//    tolerance), both at rtol 1e-12;
//  - on several ranks the mixed du equals the one computed on each rank alone (PETSC_COMM_SELF);
// with both preconditioners of the s block (selfp, mass) and both block factorizations (block
// upper triangular with FGMRES, block diagonal with MINRES).
// The state is a 2 % expansion with a random perturbation, and part of the Dirichlet set
// (box.xmin) is prescribed, so both the element terms and the elimination are exercised.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <tuple>

#include "forms/elastic_form.hpp"
#include "forms/inertia_form.hpp"
#include "mesh/box_generator.hpp"
#include "nonlinear/mixed_linear_solve.hpp"
#include "potential/incremental_potential.hpp"

namespace dipc {
namespace {

double hash_value(std::int64_t node, int c, int salt) {
  std::mt19937_64 rng(static_cast<std::uint64_t>(node * 3 + c) * 7919u + static_cast<std::uint64_t>(salt));
  return std::uniform_real_distribution<double>(-1.0, 1.0)(rng);
}

struct Results {
  std::vector<double> du_mixed, du_primal;  // 3 per input node, on every rank
  double split_product_error = 0;           // |(A + Bsᵀ Bs) v - H v| / |H v|
  PetscInt mixed_iterations = 0;
};

// Fills a global vector by input node id: f(input node, component).
template <class F>
void fill_by_input_id(const DistributedMesh& mesh, Vec v, F f) {
  PetscScalar* a;
  VecGetArray(v, &a);
  for (int n = 0; n < mesh.num_owned_nodes; ++n)
    for (int c = 0; c < 3; ++c) a[3 * n + c] = f(mesh.node_input_id[n], c);
  VecRestoreArray(v, &a);
}

std::vector<double> gather_by_input_id(const DistributedMesh& mesh, Vec v) {
  std::vector<double> mine(3 * mesh.num_global_nodes, 0.0), all(mine.size());
  const PetscScalar* a;
  VecGetArrayRead(v, &a);
  for (int n = 0; n < mesh.num_owned_nodes; ++n)
    for (int c = 0; c < 3; ++c) mine[3 * mesh.node_input_id[n] + c] = a[3 * n + c];
  VecRestoreArrayRead(v, &a);
  MPI_Allreduce(mine.data(), all.data(), static_cast<int>(all.size()), MPI_DOUBLE, MPI_SUM, mesh.comm);
  return all;
}

// One potential (consistent inertia + elasticity), split or not, on `mesh`.
std::unique_ptr<IncrementalPotential> make_potential(const DistributedMesh& mesh, const ElementData& elements, double h,
                                                     bool split) {
  std::vector<std::unique_ptr<Form>> forms;
  forms.push_back(std::make_unique<ConsistentInertiaForm>(elements));
  auto elastic = std::make_unique<ElasticForm>(elements, h * h);
  if (split) elastic->split_volumetric();
  forms.push_back(std::move(elastic));
  std::vector<char> prescribed(3 * mesh.num_local_nodes(), 0);
  for (std::int32_t n : mesh.node_sets.at("box.xmin"))
    prescribed[3 * n] = prescribed[3 * n + 1] = prescribed[3 * n + 2] = 1;
  auto potential = std::make_unique<IncrementalPotential>();
  EXPECT_EQ(potential->setup(mesh, std::move(forms), prescribed), 0);
  return potential;
}

Results solve_both(const HexMesh& whole, MPI_Comm comm, double nu, MixedSolveOptions options) {
  DistributedMesh mesh = distribute_mesh(whole, comm);
  const double E = 1e6, h = 0.005;
  BodyMaterial material{E * nu / ((1 + nu) * (1 - 2 * nu)), E / (2 * (1 + nu)), 1000};
  material.volumetric = VolumetricTerm::mean_dilatation;
  ElementData elements(mesh, {material});
  auto full = make_potential(mesh, elements, h, false);
  auto split = make_potential(mesh, elements, h, true);
  Mat H, A;
  EXPECT_EQ(full->create_matrix(&H), 0);
  EXPECT_EQ(split->create_matrix(&A), 0);
  Vec x, r, v, Hv, Kv, du;
  full->create_global_vec(&x);
  for (Vec* w : {&r, &v, &Hv, &Kv, &du}) VecDuplicate(x, w);
  {
    PetscScalar* a;
    VecGetArray(x, &a);
    for (int n = 0; n < mesh.num_owned_nodes; ++n)
      for (int c = 0; c < 3; ++c)
        a[3 * n + c] = 1.02 * mesh.coordinates[n][c] + 0.01 * hash_value(mesh.node_input_id[n], c, 1);
    VecRestoreArray(x, &a);
  }
  fill_by_input_id(mesh, r, [](std::int64_t n, int c) { return hash_value(n, c, 2); });
  fill_by_input_id(mesh, v, [](std::int64_t n, int c) { return hash_value(n, c, 3); });
  EXPECT_EQ(full->hessian(x, H), 0);
  EXPECT_EQ(split->hessian(x, A), 0);

  MixedLinearSolve mixed;
  std::vector<const VolumetricPart*> parts;
  for (const auto& form : split->forms())
    if (const VolumetricSplit* volumetric = form->volumetric_split(); volumetric && volumetric->volumetric_part())
      parts.push_back(volumetric->volumetric_part());
  EXPECT_EQ(parts.size(), 1u);
  EXPECT_EQ(mixed.setup(comm, parts, &split->prescribed_dofs(), 1e-12, 1e-50, 5000, options), 0);
  EXPECT_EQ(mixed.update(A), 0);
  EXPECT_EQ(mixed.setup_preconditioner(), 0);

  Results out;
  // The Dirichlet rows of r are zero in a Newton system (the gradient's are).
  const auto& prescribed = split->prescribed_dofs();
  {
    PetscScalar *a, *b;
    VecGetArray(r, &a);
    VecGetArray(v, &b);
    for (int k = 0; k < 3 * mesh.num_owned_nodes; ++k)
      if (prescribed[k]) a[k] = 0, b[k] = 0;
    VecRestoreArray(r, &a);
    VecRestoreArray(v, &b);
  }
  MatMult(H, v, Hv);
  EXPECT_EQ(mixed.multiply(v, Kv), 0);
  PetscReal hv_norm, diff_norm;
  VecNorm(Hv, NORM_2, &hv_norm);
  VecAXPY(Kv, -1.0, Hv);
  VecNorm(Kv, NORM_2, &diff_norm);
  out.split_product_error = diff_norm / hv_norm;

  KSPConvergedReason reason;
  EXPECT_EQ(mixed.solve(r, du, &out.mixed_iterations, &reason), 0);
  EXPECT_GT(reason, 0) << "the mixed Krylov solve did not converge: " << KSPConvergedReasons[reason];
  out.du_mixed = gather_by_input_id(mesh, du);

  KSP ksp;
  KSPCreate(comm, &ksp);
  KSPSetOperators(ksp, H, H);
  KSPSetType(ksp, KSPCG);
  PC pc;
  KSPGetPC(ksp, &pc);
  PCSetType(pc, PCHYPRE);
  KSPSetTolerances(ksp, 1e-13, 1e-50, PETSC_DEFAULT, 20000);
  KSPSolve(ksp, r, du);
  KSPGetConvergedReason(ksp, &reason);
  EXPECT_GT(reason, 0) << "CG did not converge: " << KSPConvergedReasons[reason];
  out.du_primal = gather_by_input_id(mesh, du);
  KSPDestroy(&ksp);
  for (Vec* w : {&x, &r, &v, &Hv, &Kv, &du}) VecDestroy(w);
  MatDestroy(&H);
  MatDestroy(&A);
  return out;
}

double relative_difference(const std::vector<double>& a, const std::vector<double>& b) {
  double diff = 0, norm = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    diff = std::max(diff, std::abs(a[i] - b[i]));
    norm = std::max(norm, std::abs(b[i]));
  }
  EXPECT_GT(norm, 0.0);
  return diff / norm;
}

class MixedSolve : public ::testing::TestWithParam<std::tuple<double, SchurApproximation, SchurFactorization>> {};

TEST_P(MixedSolve, EqualsPrimalSolveAndRankCount) {
  const double nu = std::get<0>(GetParam());
  MixedSolveOptions options;
  options.schur = std::get<1>(GetParam());
  options.factorization = std::get<2>(GetParam());
  MPI_Comm world = PETSC_COMM_WORLD;
  PetscOptionsSetValue(nullptr, "-pc_type", "hypre");  // the A block's preconditioner, as dipc sets it
  HexMesh whole = generate_box({0.1, 0.1, 0.1}, {4, 4, 4}, {0, 0, 0}, 0, "box");
  const Results parallel = solve_both(whole, world, nu, options);
  EXPECT_LT(parallel.split_product_error, 1e-12) << "A + Bs^T Bs differs from the assembled H";
  const double d = relative_difference(parallel.du_mixed, parallel.du_primal);
  EXPECT_LT(d, 1e-7) << "mixed du against primal du";
  int size;
  MPI_Comm_size(world, &size);
  if (size > 1) {
    const Results serial = solve_both(whole, PETSC_COMM_SELF, nu, options);
    EXPECT_LT(relative_difference(parallel.du_mixed, serial.du_mixed), 1e-7) << "mixed du, all ranks vs one";
  }
  PetscOptionsClearValue(nullptr, "-pc_type");
  int rank;
  MPI_Comm_rank(world, &rank);
  if (rank == 0)
    std::printf("nu %g, s block %s, %s: |(A + Bs^T Bs) v - H v| / |H v| = %.2e, mixed vs primal du %.2e, %d Krylov "
                "iterations\n",
                nu, options.schur == SchurApproximation::mass ? "mass" : "selfp",
                options.factorization == SchurFactorization::upper ? "upper" : "diag", parallel.split_product_error, d,
                static_cast<int>(parallel.mixed_iterations));
}

// An inner Krylov solve of the s block (options prefix -dipc_mixed_s_): a preconditioner that is
// not a fixed linear operator, which FGMRES (upper) tolerates; du must still be H⁻¹ r, on all
// ranks as on one. MINRES (diag) needs a fixed one, so the same options are refused there.
TEST(MixedSolveInnerSchurSolve, EqualsPrimalSolveWithUpperAndIsRefusedWithDiag) {
  MPI_Comm world = PETSC_COMM_WORLD;
  PetscOptionsSetValue(nullptr, "-pc_type", "hypre");
  PetscOptionsSetValue(nullptr, "-dipc_mixed_s_ksp_type", "cg");
  PetscOptionsSetValue(nullptr, "-dipc_mixed_s_ksp_rtol", "1e-2");
  HexMesh whole = generate_box({0.1, 0.1, 0.1}, {4, 4, 4}, {0, 0, 0}, 0, "box");
  MixedSolveOptions upper;
  upper.factorization = SchurFactorization::upper;
  const Results parallel = solve_both(whole, world, 0.4999, upper);
  EXPECT_LT(relative_difference(parallel.du_mixed, parallel.du_primal), 1e-7) << "mixed du against primal du";
  int size;
  MPI_Comm_size(world, &size);
  if (size > 1) {
    const Results serial = solve_both(whole, PETSC_COMM_SELF, 0.4999, upper);
    EXPECT_LT(relative_difference(parallel.du_mixed, serial.du_mixed), 1e-7) << "mixed du, all ranks vs one";
  }
  MixedSolveOptions diag;
  diag.factorization = SchurFactorization::diag;
  {
    MixedLinearSolve mixed;
    PetscPushErrorHandler(PetscReturnErrorHandler, nullptr);
    const PetscErrorCode code = mixed.setup(world, {}, nullptr, 1e-8, 1e-50, 100, diag);
    PetscPopErrorHandler();
    EXPECT_EQ(code, PETSC_ERR_USER_INPUT) << "an inner CG on the s block with MINRES must be refused";
  }
  for (const char* o : {"-pc_type", "-dipc_mixed_s_ksp_type", "-dipc_mixed_s_ksp_rtol"})
    PetscOptionsClearValue(nullptr, o);
}

INSTANTIATE_TEST_SUITE_P(NearlyIncompressibleAndCompressible, MixedSolve,
                         ::testing::Combine(::testing::Values(0.4999, 0.3, 0.0),
                                            ::testing::Values(SchurApproximation::selfp, SchurApproximation::mass),
                                            ::testing::Values(SchurFactorization::upper, SchurFactorization::diag)));

}  // namespace
}  // namespace dipc
