// Triangle-mesh obstacles in the contact barrier (contact_obstacles.hpp) through the whole
// distributed path, on 1 and 2 ranks: a box hovering d̂/4 above two open obstacle surfaces — a
// pyramid whose apex points at the box's bottom face (obstacle vertex–body triangle pairs) and
// a shallow roof whose ridge passes under the box's bottom edges (body edge–obstacle edge pairs)
// and whose slopes lie under its bottom vertices (body vertex–obstacle triangle pairs).
//  - barrier gradient and (unprojected) Hessian against finite differences, every pair kind
//    present; the projected Hessian symmetric PSD; only body rows and columns;
//  - lagged friction with a sliding obstacle: the obstacle's motion alone drags the body, and
//    barrier + friction match finite differences; a step that reverses the slip gives the next
//    Hessian the friction majorizer;
//  - the same energy and gradient on every rank count;
//  - CCD conformance: the body and an obstacle (static, moving at a velocity, or along the
//    second piece of a path) approach each other; the full step would cross, the step CCD
//    allows never does. (CCD follows the obstacle linearly between the segment's two times,
//    which these motions do exactly; a rotation's chord is what the integrator checks too.)
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>

#include "forms/contact_form.hpp"
#include "forms/friction_form.hpp"
#include "mesh/box_generator.hpp"
#include "potential/incremental_potential.hpp"
#include "support/directional_difference.hpp"

namespace dipc {
namespace {

constexpr double kGap = 0.005;  // the box's bottom face at z = 0.3, obstacle tops at 0.3 − gap

double hash_value(std::int64_t node, int c, int salt) {
  std::mt19937_64 rng(static_cast<std::uint64_t>(node * 3 + c) * 7919u + static_cast<std::uint64_t>(salt));
  return std::uniform_real_distribution<double>(-1.0, 1.0)(rng);
}

ContactParameters obstacle_parameters(PrescribedMotion roof_motion = {}) {
  ContactParameters params;
  params.dhat = 0.02;
  params.kappa = 1.0;
  params.kappa_adaptive = false;
  params.self_contact = {1};
  const double top = 0.3 - kGap;
  ContactParameters::Obstacle pyramid;
  pyramid.name = "pyramid";
  pyramid.source = "test";
  pyramid.rest = {{0.35, 0.30, top}, {0.15, 0.10, 0.1}, {0.55, 0.10, 0.1}, {0.55, 0.50, 0.1}, {0.15, 0.50, 0.1}};
  pyramid.triangles = {{0, 1, 2}, {0, 2, 3}, {0, 3, 4}, {0, 4, 1}};
  ContactParameters::Obstacle roof;
  roof.name = "roof";
  roof.source = "test";
  const double eave = top - 0.03;
  roof.rest = {{0.6, 0.0, top},  {0.6, 0.8, top},  {0.3, 0.0, eave},
               {0.3, 0.8, eave}, {0.9, 0.0, eave}, {0.9, 0.8, eave}};
  roof.triangles = {{2, 0, 1}, {2, 1, 3}, {0, 4, 5}, {0, 5, 1}};
  roof.motion = roof_motion;
  params.obstacles = {pyramid, roof};
  return params;
}

struct ObstacleFixture {
  DistributedMesh mesh;
  IncrementalPotential potential;
  ContactForm* contact = nullptr;
  Mat H = nullptr;

  FrictionForm* friction = nullptr;

  // With mu > 0 also lagged friction (ε_v = 1e-3, h = 0.01).
  ObstacleFixture(ContactParameters params, MPI_Comm comm = PETSC_COMM_WORLD, double mu = 0) {
    mesh = distribute_mesh(generate_box({0.5, 0.5, 0.5}, {2, 2, 2}, {0.21, 0.17, 0.3}, 0, "box"), comm);
    auto form = std::make_unique<ContactForm>(mesh, params);
    contact = form.get();
    std::vector<std::unique_ptr<Form>> forms;
    forms.push_back(std::move(form));
    if (mu > 0) {
      auto f = std::make_unique<FrictionForm>(*contact, mu, 1e-3, 0.01, true);
      friction = f.get();
      forms.push_back(std::move(f));
    }
    EXPECT_EQ(potential.setup(mesh, std::move(forms), std::vector<char>(3 * mesh.num_local_nodes(), 0)), 0);
    EXPECT_EQ(potential.create_matrix(&H), 0);
  }
  ~ObstacleFixture() { MatDestroy(&H); }

  void fill(Vec v, double amplitude, int salt, bool add_rest) {
    PetscScalar* a;
    VecGetArray(v, &a);
    for (int n = 0; n < mesh.num_owned_nodes; ++n)
      for (int c = 0; c < 3; ++c)
        a[3 * n + c] = (add_rest ? mesh.coordinates[n][c] : 0.0) +
                       amplitude * hash_value(mesh.node_input_id[n], c, salt);
    VecRestoreArray(v, &a);
  }

  // Active pairs at x by kind, summed over ranks: [body vertex–obstacle triangle,
  // body edge–obstacle edge, obstacle vertex–body triangle].
  std::array<long, 3> obstacle_pair_counts(Vec x) {
    std::array<long, 3> local{0, 0, 0}, total{};
    potential.with_local(x, [&](const double* xl, std::size_t) {
      for (const auto& p : contact->active_pairs(xl)) {
        if (is_obstacle_node(p.info.nodes[0]))
          ++local[2];
        else if (p.info.kind == PairKind::vertex_triangle && is_obstacle_node(p.info.nodes[1]))
          ++local[0];
        else if (p.info.kind == PairKind::edge_edge && is_obstacle_node(p.info.nodes[2]))
          ++local[1];
      }
    });
    MPI_Allreduce(local.data(), total.data(), 3, MPI_LONG, MPI_SUM, mesh.comm);
    return total;
  }
};

TEST(ContactObstacles, GradientAndExactHessianMatchDifferences) {
  ContactParameters params = obstacle_parameters();
  params.project_hessian = false;
  ObstacleFixture f(params);
  Vec x, d, w, twice;
  f.potential.create_global_vec(&x);
  for (Vec* v : {&d, &w, &twice}) VecDuplicate(x, v);
  f.fill(x, 3e-3, 1, true);
  f.fill(d, 1.0, 3, false);
  const double eps = 1e-7;
  // Candidates must cover the whole difference stencil x ± eps d.
  VecWAXPY(w, -eps, d, x);
  VecCopy(d, twice);
  VecScale(twice, 2 * eps);
  PetscReal alpha;
  ASSERT_EQ(f.potential.max_step(w, twice, &alpha), 0);
  const std::array<long, 3> kinds = f.obstacle_pair_counts(x);
  for (int k = 0; k < 3; ++k) EXPECT_GT(kinds[k], 0) << "obstacle pair kind " << k << " is never active";

  PetscReal E0;
  f.potential.objective(x, &E0);
  EXPECT_GT(E0, 0);
  test::DirectionalDifferences fd;
  ASSERT_EQ(test::directional_differences(f.potential, f.H, x, d, eps, &fd), 0);
  EXPECT_NEAR(fd.slope_fd, fd.slope, 1e-5 * std::abs(fd.slope));
  EXPECT_GT(fd.hessian_scale, 0);
  EXPECT_LT(fd.hessian_error, 1e-4 * fd.hessian_scale);
  for (Vec* v : {&x, &d, &w, &twice}) VecDestroy(v);
}

// The roof slides along x at 0.05 m/s; friction is lagged at the step's start x_start with the
// roof at t = 0 and evaluated with the roof at t = h = 0.01.
TEST(ContactObstacles, FrictionAgainstASlidingObstacleMatchesDifferences) {
  PrescribedMotion slide;
  slide.kind = PrescribedMotion::Kind::Velocity;
  slide.velocity = {0.05, 0.02, 0};
  ContactParameters params = obstacle_parameters(slide);
  params.project_hessian = false;
  ObstacleFixture f(params, PETSC_COMM_WORLD, 0.5);
  Vec x_start, x, d, g, w, twice;
  f.potential.create_global_vec(&x);
  for (Vec* v : {&x_start, &d, &g, &w, &twice}) VecDuplicate(x, v);
  f.fill(x_start, 3e-3, 1, true);
  f.contact->set().start_obstacle_step(0.0);
  ASSERT_EQ(f.potential.prepare_point(x_start), 0);
  f.potential.with_local(x_start, [&](const double* xl, std::size_t) { f.friction->update_lag(xl, xl); });
  long pairs = static_cast<long>(f.friction->num_pairs()), total = 0;
  MPI_Allreduce(&pairs, &total, 1, MPI_LONG, MPI_SUM, f.mesh.comm);
  EXPECT_GT(total, 0) << "no friction pair";
  f.contact->set().move_obstacles(0.01, 0.01);

  // The body has not moved: only the obstacle's sliding makes a friction force, along +x, +y.
  ASSERT_EQ(f.potential.prepare_point(x_start), 0);
  const Form* friction = f.friction;
  ASSERT_EQ(f.potential.partial_gradient(x_start, g, [friction](const Form& form) { return &form == friction; }), 0);
  PetscReal sum_x = 0, sum_y = 0;
  {
    const PetscScalar* a;
    VecGetArrayRead(g, &a);
    PetscInt n;
    VecGetLocalSize(g, &n);
    double local[2] = {0, 0};
    for (PetscInt i = 0; i < n; i += 3) local[0] += a[i], local[1] += a[i + 1];
    VecRestoreArrayRead(g, &a);
    double all[2];
    MPI_Allreduce(local, all, 2, MPI_DOUBLE, MPI_SUM, f.mesh.comm);
    sum_x = all[0], sum_y = all[1];
  }
  // ∂D/∂x points against the body's motion relative to the obstacle, i.e. along the obstacle's
  // velocity with a minus sign: the force −∂D/∂x drags the body along +x, +y.
  EXPECT_LT(sum_x, 0);
  EXPECT_LT(sum_y, 0);

  f.fill(x, 2e-4, 7, false);
  VecAXPY(x, 1.0, x_start);
  f.fill(d, 1.0, 3, false);
  const double eps = 1e-8;
  VecWAXPY(w, -eps, d, x);
  VecCopy(d, twice);
  VecScale(twice, 2 * eps);
  PetscReal alpha;
  ASSERT_EQ(f.potential.max_step(w, twice, &alpha), 0);
  test::DirectionalDifferences fd;
  ASSERT_EQ(test::directional_differences(f.potential, f.H, x, d, eps, &fd), 0);
  EXPECT_NEAR(fd.slope_fd, fd.slope, 1e-5 * std::abs(fd.slope));
  EXPECT_LT(fd.hessian_error, 1e-4 * fd.hessian_scale);
  for (Vec* v : {&x_start, &x, &d, &g, &w, &twice}) VecDestroy(v);
}

// FrictionForm's model of a reversal (friction_form.hpp): with the body shifted sideways from
// where friction was lagged, every pair slides; a segment that turns every slip into its
// opposite marks every pair, the next Hessian gives them their majorizer (stiffer along the
// slip: H_majorizer - H is PSD and not zero) and clears the marks; a segment along the slip, or
// none, marks no pair.
TEST(ContactObstacles, FrictionPairsWhoseSlipAStepReversesGetTheMajorizerForOneHessian) {
  ObstacleFixture f(obstacle_parameters(), PETSC_COMM_WORLD, 0.5);
  Vec x_start, x, p, v, Hv, Mv;
  f.potential.create_global_vec(&x);
  for (Vec* w : {&x_start, &p, &v, &Hv, &Mv}) VecDuplicate(x, w);
  f.fill(x_start, 3e-3, 1, true);
  f.contact->set().start_obstacle_step(0.0);
  ASSERT_EQ(f.potential.prepare_point(x_start), 0);
  f.potential.with_local(x_start, [&](const double* xl, std::size_t) { f.friction->update_lag(xl, xl); });
  const auto all_ranks = [&](std::size_t n) {
    long local = static_cast<long>(n), total = 0;
    MPI_Allreduce(&local, &total, 1, MPI_LONG, MPI_SUM, f.mesh.comm);
    return total;
  };
  const long pairs = all_ranks(f.friction->num_pairs());
  ASSERT_GT(pairs, 0);
  // p := factor * (5e-4, 2e-4, 0) on every body node (ε_u = 1e-5).
  const auto sideways = [&](Vec w, double factor) {
    PetscScalar* a;
    VecGetArray(w, &a);
    for (int n = 0; n < f.mesh.num_owned_nodes; ++n)
      a[3 * n] = factor * 5e-4, a[3 * n + 1] = factor * 2e-4, a[3 * n + 2] = 0;
    VecRestoreArray(w, &a);
  };
  sideways(x, 1.0);
  VecAXPY(x, 1.0, x_start);
  ASSERT_EQ(f.potential.prepare_point(x), 0);
  EXPECT_EQ(all_ranks(f.friction->num_reversing()), 0);
  PetscReal alpha;
  sideways(p, 1.0);  // along the slip: it grows
  ASSERT_EQ(f.potential.max_step(x, p, &alpha), 0);
  EXPECT_EQ(all_ranks(f.friction->num_reversing()), 0);
  sideways(p, -2.0);  // to the opposite slip
  ASSERT_EQ(f.potential.max_step(x, p, &alpha), 0);
  EXPECT_EQ(all_ranks(f.friction->num_reversing()), pairs);
  ASSERT_EQ(f.potential.hessian(x, f.H), 0);
  EXPECT_EQ(all_ranks(f.friction->num_reversing()), 0) << "the marks hold for one Hessian";
  Mat majorized;
  MatDuplicate(f.H, MAT_COPY_VALUES, &majorized);
  ASSERT_EQ(f.potential.hessian(x, f.H), 0);
  double least = 0, most = 0;
  for (int salt = 0; salt < 8; ++salt) {
    f.fill(v, 1.0, 11 + salt, false);
    MatMult(majorized, v, Mv);
    MatMult(f.H, v, Hv);
    PetscReal vMv, vHv;
    VecDot(v, Mv, &vMv);
    VecDot(v, Hv, &vHv);
    least = std::min(least, (vMv - vHv) / std::abs(vHv));
    most = std::max(most, (vMv - vHv) / std::abs(vHv));
  }
  EXPECT_GE(least, -1e-12);
  EXPECT_GT(most, 1e-6);
  MatDestroy(&majorized);
  for (Vec* w : {&x_start, &x, &p, &v, &Hv, &Mv}) VecDestroy(w);
}

TEST(ContactObstacles, ProjectedHessianIsSymmetricPositiveSemidefinite) {
  ObstacleFixture f(obstacle_parameters());
  Vec x, d, Hd;
  f.potential.create_global_vec(&x);
  VecDuplicate(x, &d);
  VecDuplicate(x, &Hd);
  f.fill(x, 3e-3, 1, true);
  ASSERT_EQ(f.potential.prepare_point(x), 0);
  f.potential.hessian(x, f.H);
  PetscBool symmetric;
  MatIsSymmetric(f.H, 1e-12, &symmetric);
  EXPECT_TRUE(symmetric);
  PetscReal norm;
  MatNorm(f.H, NORM_FROBENIUS, &norm);
  EXPECT_GT(norm, 0);
  for (int salt = 10; salt < 20; ++salt) {
    f.fill(d, 1.0, salt, false);
    MatMult(f.H, d, Hd);
    PetscReal q;
    VecDot(d, Hd, &q);
    EXPECT_GE(q, -1e-12) << "dᵀHd < 0";
  }
  VecDestroy(&x);
  VecDestroy(&d);
  VecDestroy(&Hd);
}

TEST(ContactObstacles, SameEnergyAndGradientOnAnyRankCount) {
  double values[2][2];
  int rank;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  MPI_Comm self;
  MPI_Comm_split(PETSC_COMM_WORLD, rank == 0 ? 0 : MPI_UNDEFINED, 0, &self);
  for (int run = 0; run < 2; ++run) {
    if (run == 1 && rank != 0) break;
    ObstacleFixture f(obstacle_parameters(), run == 0 ? PETSC_COMM_WORLD : self);
    Vec x, g;
    f.potential.create_global_vec(&x);
    VecDuplicate(x, &g);
    f.fill(x, 3e-3, 1, true);
    ASSERT_EQ(f.potential.prepare_point(x), 0);
    PetscReal E, gn;
    f.potential.objective(x, &E);
    f.potential.gradient(x, g);
    VecNorm(g, NORM_2, &gn);
    values[run][0] = E, values[run][1] = gn;
    VecDestroy(&x);
    VecDestroy(&g);
  }
  if (rank == 0) {
    EXPECT_GT(values[1][0], 0);
    EXPECT_NEAR(values[0][0], values[1][0], 1e-12 * values[1][0]);
    EXPECT_NEAR(values[0][1], values[1][1], 1e-12 * values[1][1]);
    MPI_Comm_free(&self);
  }
}

// Body moving down by `drop` while the roof moves by `motion` from time t0 to t1: the full step
// crosses (so the check can fail), the CCD-limited one never does, and it leaves a positive
// distance.
void expect_ccd_conforms(const PrescribedMotion& motion, double t0, double t1, double drop) {
  ObstacleFixture f(obstacle_parameters(motion));
  Vec x, p, w;
  f.potential.create_global_vec(&x);
  VecDuplicate(x, &p);
  VecDuplicate(x, &w);
  for (int salt = 1; salt <= 4; ++salt) {
    f.fill(x, 2e-3, salt, true);
    f.fill(p, 0.2 * drop, salt + 100, false);  // a random tilt of the motion
    PetscScalar* a;
    VecGetArray(p, &a);
    for (int n = 0; n < f.mesh.num_owned_nodes; ++n) a[3 * n + 2] -= drop;
    VecRestoreArray(p, &a);
    auto crossings_at = [&](double alpha, double* d_min) {
      f.contact->set().move_obstacles(t0 + alpha * (t1 - t0), t0 + alpha * (t1 - t0));
      VecWAXPY(w, alpha, p, x);
      EXPECT_EQ(f.potential.prepare_point(w), 0);
      long local = 0, total = 0;
      double d = 0;
      f.potential.with_local(w, [&](const double* xl, std::size_t) {
        local = f.contact->set().count_intersections(xl, nullptr);
        d = f.contact->min_distance(xl);
      });
      MPI_Allreduce(&local, &total, 1, MPI_LONG, MPI_SUM, f.mesh.comm);
      MPI_Allreduce(&d, d_min, 1, MPI_DOUBLE, MPI_MIN, f.mesh.comm);
      return total;
    };
    double d_end = 0;
    EXPECT_GT(crossings_at(1.0, &d_end), 0) << "salt " << salt << ": the full step does not cross";
    f.contact->set().move_obstacles(t0, t1);
    PetscReal alpha;
    ASSERT_EQ(f.potential.max_step(x, p, &alpha), 0);
    EXPECT_GT(alpha, 0.0);
    EXPECT_LT(alpha, 1.0);
    double d_alpha = 0;
    EXPECT_EQ(crossings_at(alpha, &d_alpha), 0) << "salt " << salt << ": the CCD step " << alpha << " crosses";
    EXPECT_GT(d_alpha, 0) << "salt " << salt;
  }
  VecDestroy(&x);
  VecDestroy(&p);
  VecDestroy(&w);
}

TEST(ContactObstacles, CcdStepNeverCrossesAStaticObstacle) { expect_ccd_conforms(PrescribedMotion{}, 0, 1, 0.2); }

TEST(ContactObstacles, CcdStepNeverCrossesARisingObstacle) {
  PrescribedMotion up;
  up.kind = PrescribedMotion::Kind::Velocity;
  up.velocity = {0.01, 0.0, 0.1};
  expect_ccd_conforms(up, 0, 1, 0.1);
}

TEST(ContactObstacles, CcdStepNeverCrossesAnObstacleOnAPath) {
  PrescribedMotion path;
  path.kind = PrescribedMotion::Kind::Path;
  path.path = {{0, 0, 0, 0}, {0.5, 0, 0, -0.02}, {1.0, 0.05, 0, 0.08}};  // down, then up into the box
  expect_ccd_conforms(path, 0.5, 1.0, 0.1);
}

}  // namespace
}  // namespace dipc

namespace dipc {
namespace {

// Path motion: piecewise linear through the keyframes, the right-hand slope as velocity, held
// after the last keyframe.
TEST(PrescribedMotionPath, InterpolatesAndHolds) {
  PrescribedMotion m;
  m.kind = PrescribedMotion::Kind::Path;
  m.path = {{0, 0, 0, 0}, {0.5, 1, 0, 0}, {1.5, 1, 2, 0}};
  const std::array<double, 3> X{1, 1, 1};
  auto expect_near = [](const std::array<double, 3>& a, const std::array<double, 3>& b) {
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(a[c], b[c], 1e-15) << c;
  };
  expect_near(m.position(X, 0.0), {1, 1, 1});
  expect_near(m.position(X, 0.25), {1.5, 1, 1});
  expect_near(m.position(X, 0.5), {2, 1, 1});
  expect_near(m.position(X, 1.0), {2, 2, 1});
  expect_near(m.position(X, 9.0), {2, 3, 1});
  expect_near(m.velocity_at(X, 0.0), {2, 0, 0});
  expect_near(m.velocity_at(X, 0.5), {0, 2, 0});
  expect_near(m.velocity_at(X, 1.5), {0, 0, 0});
}

}  // namespace
}  // namespace dipc
