// SPDX-License-Identifier: Apache-2.0
#include "server/metrics/histogram.h"

#include <thread>
#include <vector>

#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace ispq::server {
namespace {

using ::testing::ElementsAre;

// Prometheus' convention: a bucket counts observations <= its upper bound, cumulatively; what
// lies above the last bound counts only in the total.
TEST(HistogramTest, BucketsAreCumulativeAndInclusiveOfTheirBound) {
  Histogram histogram({1, 2, 5});
  for (double seconds : {0.5, 1.0, 1.5, 2.0, 4.0, 7.0}) histogram.Observe(seconds);
  const v1::Histogram proto = histogram.ToProto();
  EXPECT_THAT(proto.upper_bounds(), ElementsAre(1, 2, 5));
  EXPECT_THAT(proto.cumulative_counts(), ElementsAre(2, 4, 5));
  EXPECT_EQ(proto.count(), 6);
  EXPECT_DOUBLE_EQ(proto.sum(), 16.0);
}

TEST(HistogramTest, DefaultBoundsIncreaseFromAMillisecondToTenMinutes) {
  const std::vector<double> bounds = Histogram::DefaultSecondsBounds();
  ASSERT_FALSE(bounds.empty());
  EXPECT_EQ(bounds.front(), 0.001);
  EXPECT_EQ(bounds.back(), 600);
  for (size_t i = 1; i < bounds.size(); ++i) EXPECT_LT(bounds[i - 1], bounds[i]);
}

TEST(HistogramTest, ConcurrentObservationsAreAllCounted) {
  Histogram histogram(Histogram::DefaultSecondsBounds());
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t) {
    threads.emplace_back([&histogram] {
      for (int i = 0; i < 1000; ++i) histogram.Observe(0.002);
    });
  }
  for (std::thread& thread : threads) thread.join();
  const v1::Histogram proto = histogram.ToProto();
  EXPECT_EQ(proto.count(), 4000);
  EXPECT_EQ(proto.cumulative_counts(0), 0);
  EXPECT_EQ(proto.cumulative_counts(1), 4000);
}

}  // namespace
}  // namespace ispq::server
