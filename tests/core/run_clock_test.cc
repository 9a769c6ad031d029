// SPDX-License-Identifier: Apache-2.0
#include "core/run_clock.h"

#include <chrono>
#include <limits>

#include "gtest/gtest.h"

namespace ispq {
namespace {

TEST(RunClockTest, RunsUntilInterruptedAndThenStaysStopped) {
  SolveInterrupter interrupter;
  RunClock clock(&interrupter, std::numeric_limits<double>::infinity());
  EXPECT_FALSE(clock.ShouldStop());
  EXPECT_EQ(clock.termination(), Termination::kConverged);
  interrupter.Interrupt();
  EXPECT_TRUE(clock.ShouldStop());
  EXPECT_TRUE(clock.stopped());
  EXPECT_EQ(clock.termination(), Termination::kInterrupted);
}

// The limit counts from the clock's start: a start an hour ago is past a one-minute limit
// without any waiting in the test.
TEST(RunClockTest, StopsAtTheTimeLimitCountedFromItsStart) {
  const RunClock::Clock::time_point an_hour_ago = RunClock::Clock::now() - std::chrono::hours(1);
  RunClock late(nullptr, 60, an_hour_ago);
  EXPECT_LT(late.RemainingSeconds(), 0);
  EXPECT_GE(late.ElapsedSeconds(), 3600);
  EXPECT_TRUE(late.ShouldStop());
  EXPECT_EQ(late.termination(), Termination::kTimeLimit);

  RunClock early(nullptr, 3600);
  EXPECT_FALSE(early.ShouldStop());
  EXPECT_GT(early.RemainingSeconds(), 0);
}

TEST(RunClockTest, ScopedCpuSecondsAddsTheScopesCpuTime) {
  double sink = 0;
  {
    ScopedCpuSeconds timer(&sink);
    volatile double x = 0;
    for (int i = 0; i < 2000000; ++i) x = x + 1;
  }
  EXPECT_GT(sink, 0);
  const double after_one = sink;
  { ScopedCpuSeconds timer(&sink); }
  EXPECT_GE(sink, after_one) << "a second scope adds to the same statistic";
}

}  // namespace
}  // namespace ispq
