// SPDX-License-Identifier: Apache-2.0
#include "server/http/http_refusals.h"

#include <cstdint>
#include <map>
#include <thread>
#include <vector>

#include "gtest/gtest.h"

namespace ispq::server::http {
namespace {

// /metrics has a series for every refusal the checks give before any happened, so that rates
// and alerts work from the start.
TEST(HttpRefusalsTest, UsualStatusesArePresentAtZero) {
  const HttpRefusals refusals;
  const std::map<int, int64_t> counts = refusals.ByStatus();
  for (const int status : {400, 401, 403, 404, 411, 413, 414, 415, 421, 429, 431, 501, 503}) {
    ASSERT_TRUE(counts.contains(status)) << status;
    EXPECT_EQ(counts.at(status), 0) << status;
  }
  for (const auto& [status, count] : counts) EXPECT_EQ(count, 0) << status;
}

TEST(HttpRefusalsTest, CountsByStatusIncludingUnusualOnes) {
  HttpRefusals refusals;
  refusals.Count(413);
  refusals.Count(413);
  refusals.Count(431);
  refusals.Count(405);  // not among the usual ones: appears once counted
  const std::map<int, int64_t> counts = refusals.ByStatus();
  EXPECT_EQ(counts.at(413), 2);
  EXPECT_EQ(counts.at(431), 1);
  EXPECT_EQ(counts.at(405), 1);
  EXPECT_EQ(counts.at(400), 0);
  EXPECT_EQ(refusals.ByStatus(), counts);  // reading does not change the counts
}

TEST(HttpRefusalsTest, CountsFromManyThreadsAddUp) {
  HttpRefusals refusals;
  constexpr int kThreads = 4;
  constexpr int kEach = 1000;
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t) {
    threads.emplace_back([&refusals, t] {
      for (int i = 0; i < kEach; ++i) {
        refusals.Count(t % 2 == 0 ? 429 : 503);
        if (i % 100 == 0) refusals.ByStatus();
      }
    });
  }
  for (std::thread& thread : threads) thread.join();
  const std::map<int, int64_t> counts = refusals.ByStatus();
  EXPECT_EQ(counts.at(429), kThreads / 2 * kEach);
  EXPECT_EQ(counts.at(503), kThreads / 2 * kEach);
}

}  // namespace
}  // namespace ispq::server::http
