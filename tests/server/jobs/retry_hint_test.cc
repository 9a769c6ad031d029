// SPDX-License-Identifier: Apache-2.0
#include "server/jobs/retry_hint.h"

#include <string>

#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace ispq::server {
namespace {

using ::testing::HasSubstr;

TEST(RetryHintTest, TravelsWithTheStatusAndIsSaidInItsMessage) {
  const absl::Status status =
      ResourceExhaustedWithRetryHint("the job queue is full", absl::Milliseconds(1500));
  EXPECT_EQ(status.code(), absl::StatusCode::kResourceExhausted);
  EXPECT_THAT(std::string(status.message()), HasSubstr("the job queue is full"));
  EXPECT_THAT(std::string(status.message()), HasSubstr("retry in 1500 ms"));
  EXPECT_EQ(RetryHintOf(status), absl::Milliseconds(1500));
}

TEST(RetryHintTest, OtherStatusesHaveNone) {
  EXPECT_FALSE(RetryHintOf(absl::OkStatus()).has_value());
  EXPECT_FALSE(RetryHintOf(absl::ResourceExhaustedError("no hint")).has_value());
  EXPECT_FALSE(RetryHintOf(absl::UnavailableError("down")).has_value());
}

}  // namespace
}  // namespace ispq::server
