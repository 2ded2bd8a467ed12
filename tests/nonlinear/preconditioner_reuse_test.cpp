// ReuseCycle, the rebuild rule of -dipc_pc_reuse, in units of CG iterations: a rebuild costs S
// (the setup) plus its solve's CG iterations, a reuse its solve's. Rebuild first, for a new
// pattern, after a failed solve or a decision whose solve never ran, and once the latest
// iteration costs more than the cycle's average (C_n > A_n); reuse otherwise. A reused solve
// may take at most max(2 (S + k_0), 10) CG iterations.
#include <gtest/gtest.h>

#include "nonlinear/preconditioner_reuse.hpp"

namespace dipc {
namespace {

TEST(ReuseCycle, RebuildsFirstThenReusesWhileTheLatestCostStaysBelowTheAverage) {
  ReuseCycle c(40);
  EXPECT_TRUE(c.decide(false));  // nothing built yet
  c.record(10, false);           // C_0 = 40 + 10
  EXPECT_DOUBLE_EQ(c.last_cost(), 50);
  EXPECT_FALSE(c.decide(false));
  c.record(12, false);  // A_1 = 31
  EXPECT_FALSE(c.decide(false));
  c.record(14, false);  // A_2 = 76 / 3 = 25.3
  EXPECT_FALSE(c.decide(false));
  c.record(20, false);  // A_3 = 24
  EXPECT_FALSE(c.decide(false));
  c.record(24, false);  // A_4 = 24: C_4 = A_4 is not above it
  EXPECT_DOUBLE_EQ(c.average_cost(), 24);
  EXPECT_FALSE(c.decide(false));
  c.record(25, false);  // A_5 = 145 / 6 = 24.17 < 25
  EXPECT_TRUE(c.decide(false));
  EXPECT_TRUE(c.rebuilding());
  c.record(11, false);  // a new cycle starts from this solve alone, setup included
  EXPECT_DOUBLE_EQ(c.average_cost(), 51);
  EXPECT_FALSE(c.decide(false));
}

TEST(ReuseCycle, ACheapSetupRebuildsSooner) {
  // The same solves as above with S = 4: C_0 = 14, C_1 = 12, C_2 = 14 > A_2 = 40 / 3.
  ReuseCycle c(4);
  EXPECT_TRUE(c.decide(false));
  c.record(10, false);
  EXPECT_FALSE(c.decide(false));
  c.record(12, false);
  EXPECT_FALSE(c.decide(false));
  c.record(14, false);
  EXPECT_TRUE(c.decide(false));
}

TEST(ReuseCycle, ConstantSolvesNeverRebuild) {
  // With the hierarchy as good as new, every reuse saves S: the average only falls towards k.
  ReuseCycle c(10);
  EXPECT_TRUE(c.decide(false));
  c.record(8, false);
  for (int i = 0; i < 100; ++i) {
    EXPECT_FALSE(c.decide(false)) << i;
    c.record(8, false);
  }
}

TEST(ReuseCycle, ANewPatternAlwaysRebuilds) {
  ReuseCycle c(40);
  c.decide(false);
  c.record(10, false);
  EXPECT_FALSE(c.decide(false));
  c.record(1, false);
  EXPECT_TRUE(c.decide(true));
}

TEST(ReuseCycle, AFailedSolveRebuildsTheNextOne) {
  ReuseCycle c(40);
  c.decide(false);
  c.record(10, false);
  EXPECT_FALSE(c.decide(false));
  c.record(1, true);  // cheap, but failed
  EXPECT_TRUE(c.decide(false));
}

TEST(ReuseCycle, ADecisionWhoseSolveNeverRanRebuilds) {
  ReuseCycle c(40);
  c.decide(false);
  c.record(10, false);
  EXPECT_FALSE(c.decide(false));  // ... and the iteration stopped before its solve
  EXPECT_TRUE(c.decide(false));
}

TEST(ReuseCycle, AReusedSolveIsCappedAtTwiceTheRebuildIteration) {
  ReuseCycle c(40);
  c.decide(false);
  c.record(15, false);
  EXPECT_EQ(c.reused_solve_limit(), 110);  // 2 (40 + 15)
  EXPECT_FALSE(c.decide(false));
  c.record(30, false);
  EXPECT_EQ(c.reused_solve_limit(), 110);  // k_0 is the rebuild's solve, not the latest
  ReuseCycle cheap(0.5);
  cheap.decide(false);
  cheap.record(1, false);
  EXPECT_EQ(cheap.reused_solve_limit(), 10);  // never below 10
}

TEST(ReuseCycle, TheSameCountsGiveTheSameDecisions) {
  // Nothing but the counts enters: two cycles fed the same sequence decide alike.
  const long long counts[] = {9, 9, 11, 30, 12, 12, 13, 40, 8, 9, 10, 10, 11, 12, 14, 15};
  ReuseCycle a(10), b(10);
  for (long long k : counts) {
    EXPECT_EQ(a.decide(k == 40), b.decide(k == 40));
    a.record(k, false);
    b.record(k, false);
  }
}

}  // namespace
}  // namespace dipc
