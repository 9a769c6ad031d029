// SPDX-License-Identifier: Apache-2.0
// LogThrottle (server/logging/log_throttle.h): one line per interval, and the count of those held
// back.
#include "server/logging/log_throttle.h"

#include "gtest/gtest.h"

namespace ispq::server {
namespace {

TEST(LogThrottleTest, AdmitsOneLinePerIntervalAndCountsTheOthers) {
  LogThrottle throttle(absl::Seconds(10));
  const absl::Time start = absl::FromUnixSeconds(1000);
  EXPECT_EQ(throttle.Admit(start), std::optional<int64_t>(0));
  for (int i = 1; i <= 500; ++i) {
    EXPECT_EQ(throttle.Admit(start + absl::Milliseconds(i)), std::nullopt);
  }
  EXPECT_EQ(throttle.Admit(start + absl::Seconds(10)), std::optional<int64_t>(500));
  EXPECT_EQ(throttle.Admit(start + absl::Seconds(11)), std::nullopt);
  EXPECT_EQ(throttle.Admit(start + absl::Seconds(30)), std::optional<int64_t>(1));
}

}  // namespace
}  // namespace ispq::server
