// ReuseCycle, the rebuild rule of -dipc_pc_reuse: rebuild first, for a new pattern, after a
// failed solve or a decision whose solve never ran, and once the latest iteration costs more
// than the cycle's average (T_n > A_n); reuse otherwise.
#include <gtest/gtest.h>

#include "nonlinear/preconditioner_reuse.hpp"

namespace dipc {
namespace {

TEST(ReuseCycle, RebuildsFirstThenReusesWhileTheLatestCostStaysBelowTheAverage) {
  ReuseCycle c;
  EXPECT_TRUE(c.decide(false));  // nothing built yet
  c.record(10.0, false);         // T_0: setup + solve
  EXPECT_FALSE(c.decide(false));
  c.record(2.0, false);          // A_1 = 6
  EXPECT_FALSE(c.decide(false));
  c.record(3.0, false);          // A_2 = 5
  EXPECT_FALSE(c.decide(false));
  c.record(5.0, false);          // A_3 = 5: T_3 = A_3 is not above it
  EXPECT_FALSE(c.decide(false));
  c.record(5.5, false);          // A_4 = 5.1 < 5.5
  EXPECT_TRUE(c.decide(false));
  EXPECT_TRUE(c.rebuilding());
  c.record(10.0, false);         // a new cycle starts from this solve alone
  EXPECT_DOUBLE_EQ(c.average_seconds(), 10.0);
  EXPECT_FALSE(c.decide(false));
}

TEST(ReuseCycle, ANewPatternAlwaysRebuilds) {
  ReuseCycle c;
  c.decide(false);
  c.record(10.0, false);
  EXPECT_FALSE(c.decide(false));
  c.record(1.0, false);
  EXPECT_TRUE(c.decide(true));
}

TEST(ReuseCycle, AFailedSolveRebuildsTheNextOne) {
  ReuseCycle c;
  c.decide(false);
  c.record(10.0, false);
  EXPECT_FALSE(c.decide(false));
  c.record(1.0, true);  // cheap, but failed
  EXPECT_TRUE(c.decide(false));
}

TEST(ReuseCycle, ADecisionWhoseSolveNeverRanRebuilds) {
  ReuseCycle c;
  c.decide(false);
  c.record(10.0, false);
  EXPECT_FALSE(c.decide(false));  // ... and the iteration stopped before its solve
  EXPECT_TRUE(c.decide(false));
}

}  // namespace
}  // namespace dipc
