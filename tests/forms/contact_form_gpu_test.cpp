// ContactForm on the device against ContactForm on the host, on one rank: a slab on a ground
// plane and a box above it, moving into the slab. Both forms see the same hooks on host arrays,
// except prepare_segment, which the device form gets on device copies of x and p (its broad
// phase runs there); it evaluates on device copies too. Checked: the same candidates (the same
// smallest distance over them; the device list described there from the pairs' indices equal
// to the host list uploaded), the same COO pattern, energy, gradient and Hessian values to
// 1e-12 relative to the largest entry (projected and exact Hessians), a pattern change followed
// on the device, lagged friction
// over the active pairs (FrictionForm in both spaces, majorizers included), and a CCD step
// bound no larger than the host's (the host shortens each pair's search to the smallest time so
// far, see contact_form.hpp). The same with triangle-mesh obstacles (a box hovering over a
// pyramid and a moving roof, as contact_obstacles_test.cpp): the same active pairs of every
// body–obstacle kind, terms, pattern and, bit for bit, CCD bound with the obstacle moving, and
// terms after the obstacle moved on. Skips where no GPU is present.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "contact_test_scene.hpp"
#include "device/device_runtime.hpp"
#include "forms/contact_form.hpp"
#include "forms/friction_form.hpp"
#include "mesh/box_generator.hpp"

namespace dipc {
namespace {

double max_abs(const std::vector<double>& v) {
  double m = 0;
  for (double a : v) m = std::max(m, std::abs(a));
  return m;
}

double max_difference(const std::vector<double>& a, const std::vector<double>& b) {
  double m = 0;
  for (std::size_t k = 0; k < a.size(); ++k) m = std::max(m, std::abs(a[k] - b[k]));
  return m;
}

struct TwoForms {
  DistributedMesh mesh;
  std::unique_ptr<ContactForm> host, gpu;
  device::Array<double> x_device{"test x"}, p_device{"test p"};

  TwoForms(const HexMesh& whole = slab_and_box(0.29), const ContactParameters& params = slab_and_box_parameters()) {
    mesh = distribute_mesh(whole, PETSC_COMM_WORLD);
    host = std::make_unique<ContactForm>(mesh, params);
    gpu = std::make_unique<ContactForm>(mesh, params, MemorySpace::device);
  }

  void move_obstacles(double t0, double t1) {
    for (ContactForm* f : {host.get(), gpu.get()}) f->set().move_obstacles(t0, t1);
  }

  // The hooks of both forms on the segment x + αp, α ∈ [0, 1], each prepare_segment in its
  // form's memory space.
  void prepare(const std::vector<double>& x, const std::vector<double>& p) {
    x_device.upload(x);
    p_device.upload(p);
    for (ContactForm* f : {host.get(), gpu.get()})
      EXPECT_FALSE(f->update_extra_nodes(x.data(), p.data())) << "one rank has no extra nodes";
    host->prepare_segment(x.data(), p.data());
    gpu->prepare_segment(x_device.data(), p_device.data());
    expect_candidates_described_as_uploaded();
    std::vector<double> end(x.size());
    for (std::size_t k = 0; k < x.size(); ++k) end[k] = x[k] + p[k];
    EXPECT_EQ(gpu->min_distance(x.data()), host->min_distance(x.data()));
    EXPECT_EQ(gpu->min_distance(end.data()), host->min_distance(end.data()));
  }

  // The device form's candidate list, described on the device from the pairs' indices, equals
  // its host list uploaded, field by field and bit for bit.
  void expect_candidates_described_as_uploaded() {
    device::DeviceContactPairs uploaded;
    uploaded.upload(gpu->candidate_pair_list());
    const device::DeviceContactPairs& built = gpu->device_candidates();
    ASSERT_GT(uploaded.count, 0u) << "no candidate pair: the comparison would be vacuous";
    ASSERT_EQ(built.count, uploaded.count);
    EXPECT_EQ(built.hessian_values, uploaded.hessian_values);
    EXPECT_EQ(built.kind.to_host(), uploaded.kind.to_host());
    EXPECT_EQ(built.nodes.to_host(), uploaded.nodes.to_host());
    EXPECT_EQ(built.weight.to_host(), uploaded.weight.to_host());
    EXPECT_EQ(built.eps_x.to_host(), uploaded.eps_x.to_host());
    EXPECT_EQ(built.plane.to_host(), uploaded.plane.to_host());
    EXPECT_EQ(built.hessian_offset.to_host(), uploaded.hessian_offset.to_host());
  }

  // Energy, gradient and Hessian of both forms at x (after update_pattern), compared.
  void expect_same_terms(const std::vector<double>& x) {
    x_device.upload(x);
    host->update_pattern(x.data(), nullptr);
    gpu->update_pattern(x.data(), x_device.data());
    EXPECT_EQ(host->pattern_version(), gpu->pattern_version());
    std::vector<PetscInt> rows, cols, gpu_rows, gpu_cols;
    host->coo_pattern(&rows, &cols);
    gpu->coo_pattern(&gpu_rows, &gpu_cols);
    ASSERT_EQ(rows, gpu_rows);
    ASSERT_EQ(cols, gpu_cols);
    ASSERT_FALSE(rows.empty()) << "no pair is active: the test would be vacuous";
    x_device.upload(x);

    double host_energy = 0, gpu_energy = 0;
    ASSERT_TRUE(host->value(x.data(), &host_energy));
    ASSERT_TRUE(gpu->value(x_device.data(), &gpu_energy));
    EXPECT_NEAR(gpu_energy, host_energy, 1e-12 * host_energy);

    std::vector<double> g(x.size(), 0.0);
    device::Array<double> g_device("test gradient");
    g_device.resize(x.size());
    g_device.set_zero();
    ASSERT_TRUE(host->gradient(x.data(), g.data()));
    ASSERT_TRUE(gpu->gradient(x_device.data(), g_device.data()));
    EXPECT_LE(max_difference(g_device.to_host(), g), 1e-12 * max_abs(g));

    std::vector<double> H(rows.size());
    device::Array<double> H_device("test Hessian");
    H_device.resize(rows.size());
    ASSERT_TRUE(host->hessian(x.data(), H.data()));
    ASSERT_TRUE(gpu->hessian(x_device.data(), H_device.data()));
    EXPECT_LE(max_difference(H_device.to_host(), H), 1e-12 * max_abs(H));
    // The unprojected Hessians (-dipc_contact_exact_hessian) the same way.
    for (ContactForm* f : {host.get(), gpu.get()}) EXPECT_TRUE(f->set_exact_hessian(true));
    ASSERT_TRUE(host->hessian(x.data(), H.data()));
    ASSERT_TRUE(gpu->hessian(x_device.data(), H_device.data()));
    EXPECT_LE(max_difference(H_device.to_host(), H), 1e-12 * max_abs(H)) << "exact";
    for (ContactForm* f : {host.get(), gpu.get()}) f->set_exact_hessian(false);
  }
};

// Lagged friction of both forms' active pairs at x (the step started at x shifted by up to
// 2e-4 per coordinate, so that pairs slide and stick): FrictionForm on the device against the
// host, value, gradient and Hessian to 1e-12 of the largest entry, then the same after a segment
// that reverses the slips (the majorizer's Hessian for the pairs it marks), and the marks used
// up by that Hessian. x must be where the forms' candidates were last searched. reversals: the
// segment must mark some pair (where the pairs' slips come from the bodies' motion: with a moving
// obstacle under them, the obstacle's own displacement over the step can outweigh the reversal).
void expect_same_friction(TwoForms& f, const std::vector<double>& x, std::uint64_t seed, bool reversals) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<double> start(x.size()), back(x.size());
  for (std::size_t k = 0; k < x.size(); ++k) {
    start[k] = x[k] - 2e-4 * u(rng);
    back[k] = 3.0 * (start[k] - x[k]);  // across the start: every sliding pair reverses
  }
  FrictionForm host(*f.host, 0.5, 1e-2, 1e-2, true), gpu(*f.gpu, 0.5, 1e-2, 1e-2, true);
  EXPECT_EQ(gpu.memory_space(), MemorySpace::device);
  host.update_lag(x.data(), start.data());
  gpu.update_lag(x.data(), start.data());
  ASSERT_GT(host.num_pairs(), 0u) << "no friction pair: the comparison would be vacuous";
  ASSERT_EQ(gpu.num_pairs(), host.num_pairs());
  std::vector<NodeGroup> groups, gpu_groups;
  host.node_groups(&groups);
  gpu.node_groups(&gpu_groups);
  ASSERT_EQ(gpu_groups.size(), groups.size());
  std::size_t values = 0;
  for (const NodeGroup& g : groups) values += 9 * static_cast<std::size_t>(g.count) * g.count;
  device::Array<double> x_device("test x"), p_device("test p");
  x_device.upload(x);
  p_device.upload(back);

  double host_energy = 0, gpu_energy = 0;
  ASSERT_TRUE(host.value(x.data(), &host_energy));
  ASSERT_TRUE(gpu.value(x_device.data(), &gpu_energy));
  EXPECT_GT(host_energy, 0.0);
  EXPECT_NEAR(gpu_energy, host_energy, 1e-12 * host_energy);
  std::vector<double> g(x.size(), 0.0);
  device::Array<double> g_device("test gradient");
  g_device.resize(x.size());
  g_device.set_zero();
  ASSERT_TRUE(host.gradient(x.data(), g.data()));
  ASSERT_TRUE(gpu.gradient(x_device.data(), g_device.data()));
  EXPECT_LE(max_difference(g_device.to_host(), g), 1e-12 * max_abs(g));
  for (bool reversed : {false, true}) {
    if (reversed) {
      host.prepare_segment(x.data(), back.data());
      gpu.prepare_segment(x_device.data(), p_device.data());
      if (reversals) {
        EXPECT_GT(host.num_reversing(), 0u);
      }
      EXPECT_EQ(gpu.num_reversing(), host.num_reversing());
    }
    std::vector<double> H(values);
    device::Array<double> H_device("test Hessian");
    H_device.resize(values);
    ASSERT_TRUE(host.hessian(x.data(), H.data()));
    ASSERT_TRUE(gpu.hessian(x_device.data(), H_device.data()));
    EXPECT_LE(max_difference(H_device.to_host(), H), 1e-12 * max_abs(H)) << (reversed ? "majorizers" : "projected");
    EXPECT_EQ(gpu.num_reversing(), 0u);
  }
}

TEST(ContactFormGpu, DeviceFormMatchesHostForm) {
  if (device::device_count() == 0) GTEST_SKIP() << "no CUDA device";
  int size = 1;
  MPI_Comm_size(PETSC_COMM_WORLD, &size);
  if (size != 1) GTEST_SKIP() << "one rank only: the test fills the local arrays itself";
  TwoForms f;
  EXPECT_EQ(f.host->memory_space(), MemorySpace::host);
  EXPECT_EQ(f.gpu->memory_space(), MemorySpace::device);

  // x: the rest state jittered by 1e-3 (the box 0.03 above the slab, beyond d̂; only the slab's
  // bottom vertices are active, against the plane); p: the box moves 0.04 down, through the slab.
  const int n = f.mesh.num_local_nodes();
  std::vector<double> x(3 * n), p(3 * n);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) {
      x[3 * i + c] = f.mesh.coordinates[i][c] + 1e-3 * u(rng);
      p[3 * i + c] = 1e-4 * u(rng) - (c == 2 && f.mesh.coordinates[i][2] > 0.262 ? 0.04 : 0.0);
    }
  f.prepare(x, p);
  f.expect_same_terms(x);

  // Half-way along p the box is 0.01 above the slab: box–slab pairs of every kind become active
  // and the pattern changes.
  const long version = f.gpu->pattern_version();
  std::vector<double> closer(x.size());
  for (std::size_t k = 0; k < x.size(); ++k) closer[k] = x[k] + 0.5 * p[k];
  f.expect_same_terms(closer);
  EXPECT_GT(f.gpu->pattern_version(), version);
  expect_same_friction(f, closer, 7, true);

  f.x_device.upload(x);
  const double host_step = f.host->max_step(x.data(), p.data());
  const double gpu_step = f.gpu->max_step(f.x_device.data(), f.p_device.data());
  EXPECT_LT(host_step, 1.0) << "the box must hit the slab along p";
  EXPECT_GT(gpu_step, 0.0);
  EXPECT_LE(gpu_step, host_step);

  // No motion: no bound from either.
  const std::vector<double> zero(x.size(), 0.0);
  f.prepare(x, zero);
  EXPECT_EQ(f.host->max_step(x.data(), zero.data()), 1.0);
  EXPECT_EQ(f.gpu->max_step(f.x_device.data(), f.p_device.data()), 1.0);

  EXPECT_GT(f.gpu->stats().broad_phase_seconds, 0.0);
  EXPECT_GT(f.gpu->stats().transfer_seconds, 0.0);
  EXPECT_GT(f.gpu->stats().barrier_seconds, 0.0);
  EXPECT_GT(f.gpu->stats().ccd_seconds, 0.0);
}

// The obstacles of contact_obstacles_test.cpp under a 2×2×2 box whose bottom face is at z = 0.3:
// a pyramid whose apex is kGap below the box's bottom face (obstacle vertex–body triangle
// pairs) and a roof whose ridge runs kGap under the box's bottom edges (body edge–obstacle edge
// pairs) and whose slopes lie under its bottom vertices (body vertex–obstacle triangle pairs),
// here rising at `roof_velocity`.
constexpr double kGap = 0.005;

ContactParameters obstacle_parameters(const std::array<double, 3>& roof_velocity) {
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
  roof.motion.kind = PrescribedMotion::Kind::Velocity;
  roof.motion.velocity = roof_velocity;
  params.obstacles = {pyramid, roof};
  return params;
}

TEST(ContactFormGpu, ObstaclesMatchHostForm) {
  if (device::device_count() == 0) GTEST_SKIP() << "no CUDA device";
  int size = 1;
  MPI_Comm_size(PETSC_COMM_WORLD, &size);
  if (size != 1) GTEST_SKIP() << "one rank only: the test fills the local arrays itself";
  TwoForms f(generate_box({0.5, 0.5, 0.5}, {2, 2, 2}, {0.21, 0.17, 0.3}, 0, "box"),
             obstacle_parameters({0.02, 0.01, 0.02}));

  // x: the rest state jittered by 1e-3; p: the box moves 0.01 down (through the obstacles,
  // kGap below), while the roof rises 0.002 from t = 0 to 0.1.
  const int n = f.mesh.num_local_nodes();
  std::vector<double> x(3 * n), p(3 * n);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) {
      x[3 * i + c] = f.mesh.coordinates[i][c] + 1e-3 * u(rng);
      p[3 * i + c] = 1e-4 * u(rng) - (c == 2 ? 0.01 : 0.0);
    }
  f.move_obstacles(0.0, 0.1);
  f.prepare(x, p);

  // The device broad phase found the host's candidates: the same active pairs, in the same
  // order, with every body–obstacle kind present.
  const auto host_pairs = f.host->active_pairs(x.data());
  const auto gpu_pairs = f.gpu->active_pairs(x.data());
  ASSERT_EQ(gpu_pairs.size(), host_pairs.size());
  int kinds[3] = {0, 0, 0};  // body vertex–obstacle triangle, body edge–obstacle edge, obstacle vertex–body triangle
  for (std::size_t i = 0; i < host_pairs.size(); ++i) {
    const auto& a = host_pairs[i].info;
    const auto& b = gpu_pairs[i].info;
    EXPECT_EQ(a.kind, b.kind);
    EXPECT_EQ(a.nodes, b.nodes);
    EXPECT_EQ(a.weight, b.weight);
    EXPECT_EQ(a.eps_x, b.eps_x);
    if (is_obstacle_node(a.nodes[0]))
      ++kinds[2];
    else if (a.kind == PairKind::vertex_triangle && is_obstacle_node(a.nodes[1]))
      ++kinds[0];
    else if (a.kind == PairKind::edge_edge && is_obstacle_node(a.nodes[2]))
      ++kinds[1];
  }
  for (int k = 0; k < 3; ++k) EXPECT_GT(kinds[k], 0) << "no active body–obstacle pair of kind " << k;
  f.expect_same_terms(x);
  expect_same_friction(f, x, 11, false);

  // CCD with the roof moving: the same bound bit for bit (both search every pair on [0, 1]).
  f.x_device.upload(x);
  const double host_step = f.host->max_step(x.data(), p.data());
  const double gpu_step = f.gpu->max_step(f.x_device.data(), f.p_device.data());
  EXPECT_LT(host_step, 1.0) << "the box must hit the obstacles along p";
  EXPECT_EQ(gpu_step, host_step);
  // The body still, only the roof moving: from t = 0 to 0.5 it rises 1 cm, through the box's
  // bottom (5 mm ± 1 mm above the ridge), so its motion alone bounds the step.
  const std::vector<double> zero(x.size(), 0.0);
  f.move_obstacles(0.0, 0.5);
  f.prepare(x, zero);
  const double roof_host = f.host->max_step(x.data(), zero.data());
  const double roof_gpu = f.gpu->max_step(f.x_device.data(), f.p_device.data());
  EXPECT_LT(roof_host, 1.0) << "the rising roof must reach the box";
  EXPECT_EQ(roof_gpu, roof_host);

  // The obstacles moved on and stand still (a later step): the device sees their new positions.
  f.move_obstacles(0.05, 0.05);
  f.prepare(x, zero);
  EXPECT_EQ(f.host->max_step(x.data(), zero.data()), 1.0);
  EXPECT_EQ(f.gpu->max_step(f.x_device.data(), f.p_device.data()), 1.0);
  f.expect_same_terms(x);
}

}  // namespace
}  // namespace dipc
