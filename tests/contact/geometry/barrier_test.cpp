// Tests of the IPC barrier (barrier.hpp): closed-form values, the barrier's shape (positive,
// decreasing, convex on (0, d_hat), infinite at contact), central finite differences of
// b -> b' -> b'' for d_hat from 1e-5 to 1e-1 and d across (0, d_hat), and the C2 join at
// d_hat (b, b', b'' vanish with their leading asymptotic terms d_hat^2 delta^3,
// -3 d_hat delta^2, 6 delta for d = d_hat (1 - delta)).
#include "contact/geometry/barrier.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "support/finite_difference.hpp"

namespace dipc::contact {
namespace {

const double kActivationDistances[] = {1e-5, 1e-4, 1e-3, 1e-2, 1e-1};

TEST(Barrier, ClosedFormValues) {
  for (double dhat : kActivationDistances) {
    // ln(d / d_hat) = -1 at d = d_hat / e: b = (d - d_hat)^2, b' = 2 (d - d_hat) - (d - d_hat)^2 / d,
    // b'' = 2 - (d - d_hat)(3 d + d_hat) / d^2.
    const double d = dhat / std::exp(1.0);
    const double gap = d - dhat;
    EXPECT_NEAR(barrier(d, dhat), gap * gap, 1e-14 * gap * gap);
    EXPECT_NEAR(barrier_first_derivative(d, dhat), 2.0 * gap - gap * gap / d, 1e-13 * std::abs(gap));
    EXPECT_NEAR(barrier_second_derivative(d, dhat), 2.0 - gap * (3.0 * d + dhat) / (d * d), 1e-12);
  }
}

TEST(Barrier, PositiveDecreasingConvexAndInfiniteAtContact) {
  for (double dhat : kActivationDistances)
    for (double ratio : {1e-12, 1e-6, 1e-3, 0.1, 0.5, 0.9, 0.999}) {
      const double d = ratio * dhat;
      EXPECT_GT(barrier(d, dhat), 0.0);
      EXPECT_LT(barrier_first_derivative(d, dhat), 0.0);
      EXPECT_GT(barrier_second_derivative(d, dhat), 0.0);
    }
  for (double d : {0.0, -1e-9}) {
    EXPECT_EQ(barrier(d, 1e-3), INFINITY);
    EXPECT_EQ(barrier_first_derivative(d, 1e-3), -INFINITY);
    EXPECT_EQ(barrier_second_derivative(d, 1e-3), INFINITY);
  }
  for (double d : {1e-3, 2e-3, 1.0}) {
    EXPECT_EQ(barrier(d, 1e-3), 0.0);
    EXPECT_EQ(barrier_first_derivative(d, 1e-3), 0.0);
    EXPECT_EQ(barrier_second_derivative(d, 1e-3), 0.0);
  }
}

TEST(Barrier, DerivativesMatchFiniteDifferences) {
  for (double dhat : kActivationDistances)
    for (double ratio : {1e-6, 1e-4, 1e-2, 0.1, 0.3, 0.5, 0.7, 0.9, 0.99, 0.999}) {
      const double d = ratio * dhat;
      // The step stays inside (0, d_hat) and resolves both ends' length scales.
      const double h = 1e-4 * std::min(d, dhat - d);
      const double fd1 = dipc::test::central_difference_gradient([&](const double* t) { return barrier(*t, dhat); }, &d,
                                                                 1, h)[0];
      const double fd2 = dipc::test::central_difference_gradient(
          [&](const double* t) { return barrier_first_derivative(*t, dhat); }, &d, 1, h)[0];
      const double b1 = barrier_first_derivative(d, dhat), b2 = barrier_second_derivative(d, dhat);
      EXPECT_NEAR(fd1, b1, 1e-6 * std::abs(b1)) << "dhat " << dhat << " d/dhat " << ratio;
      EXPECT_NEAR(fd2, b2, 1e-6 * std::abs(b2)) << "dhat " << dhat << " d/dhat " << ratio;
    }
}

TEST(Barrier, VanishesToSecondOrderAtActivationDistance) {
  for (double dhat : kActivationDistances) {
    EXPECT_EQ(barrier(dhat, dhat), 0.0);
    EXPECT_EQ(barrier_first_derivative(dhat, dhat), 0.0);
    EXPECT_EQ(barrier_second_derivative(dhat, dhat), 0.0);
    for (double delta : {1e-3, 1e-5, 1e-7}) {
      const double d = dhat * (1.0 - delta);
      // -(delta d_hat)^2 ln(1 - delta) = d_hat^2 (delta^3 + delta^4 / 2 + ...), and so on.
      EXPECT_NEAR(barrier(d, dhat) / (dhat * dhat * delta * delta * delta), 1.0, 2.0 * delta) << delta;
      EXPECT_NEAR(barrier_first_derivative(d, dhat) / (-3.0 * dhat * delta * delta), 1.0, 4.0 * delta) << delta;
      EXPECT_NEAR(barrier_second_derivative(d, dhat) / (6.0 * delta), 1.0, 4.0 * delta) << delta;
    }
  }
}

}  // namespace
}  // namespace dipc::contact
