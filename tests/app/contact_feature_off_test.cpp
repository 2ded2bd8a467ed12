// Models only what a scene needs, and the contact forms change nothing when they should not:
// (1) the beam scene with contact enabled and a ground plane far below it (never within d̂)
// gives the same trajectory as with contact disabled; (2) friction configured with μ = 0 (and
// several lag iterations) gives the same trajectory as no friction at all.
#include <gtest/gtest.h>

#include <cmath>

#include "app/simulation.hpp"

namespace dipc {
namespace {

double max_difference(const std::vector<double>& a, const std::vector<double>& b) {
  double d = 0;
  for (std::size_t i = 0; i < a.size(); ++i) d = std::max(d, std::abs(a[i] - b[i]));
  return d;
}

RunOptions quiet_options(int steps) {
  RunOptions o;
  o.steps = steps;
  o.write_output = false;
  o.quiet = true;
  o.report = false;
  o.velocity_tol = 1e-8;
  return o;
}

TEST(FeatureOff, ContactFarAwayChangesNothing) {
  Scene plain = beam_scene();
  Scene with_contact = plain;
  with_contact.contact.enabled = true;
  with_contact.contact.planes.push_back({{0, 0, -10}, {0, 0, 1}});
  RunResult a, b;
  ASSERT_EQ(run_scene(plain, PETSC_COMM_WORLD, quiet_options(8), &a), 0);
  ASSERT_EQ(run_scene(with_contact, PETSC_COMM_WORLD, quiet_options(8), &b), 0);
  ASSERT_TRUE(a.failure.empty() && b.failure.empty()) << a.failure << b.failure;
  EXPECT_EQ(b.max_contact_pairs, 0);
  int rank;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  if (rank == 0) {
    EXPECT_LE(max_difference(a.positions, b.positions), 1e-12);
  }
}

TEST(FeatureOff, ZeroFrictionEqualsNoFriction) {
  Scene frictionless = default_scene();
  frictionless.contact.friction = 0;
  Scene configured = frictionless;
  configured.contact.epsv = 1e-4;
  configured.contact.friction_iterations = 3;
  RunResult a, b;
  ASSERT_EQ(run_scene(frictionless, PETSC_COMM_WORLD, quiet_options(12), &a), 0);
  ASSERT_EQ(run_scene(configured, PETSC_COMM_WORLD, quiet_options(12), &b), 0);
  ASSERT_TRUE(a.failure.empty() && b.failure.empty()) << a.failure << b.failure;
  EXPECT_GT(a.max_contact_pairs, 0);
  int rank;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  if (rank == 0) {
    EXPECT_LE(max_difference(a.positions, b.positions), 1e-12);
  }
}

}  // namespace
}  // namespace dipc
