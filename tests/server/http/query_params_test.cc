// SPDX-License-Identifier: Apache-2.0
#include "server/http/query_params.h"

#include <cstdint>
#include <string>
#include <utility>

#include "absl/status/status.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "server/http/http_message.h"

namespace ispq::server::http {
namespace {

using ::testing::HasSubstr;

HttpRequest WithQuery(HttpFields query) {
  HttpRequest request;
  request.query = std::move(query);
  return request;
}

TEST(QueryParamsTest, IntParamFallsBackWhenAbsent) {
  const absl::StatusOr<int64_t> value =
      IntParam(WithQuery({{"other", "5"}}), "page_size", 50, 0, 1000);
  ASSERT_TRUE(value.ok());
  EXPECT_EQ(*value, 50);
}

TEST(QueryParamsTest, IntParamTakesTheBoundsThemselves) {
  for (const auto& [text, expected] : {std::pair{"0", int64_t{0}}, std::pair{"1000", int64_t{1000}},
                                       std::pair{"7", int64_t{7}}, std::pair{"-0", int64_t{0}}}) {
    const absl::StatusOr<int64_t> value =
        IntParam(WithQuery({{"page_size", text}}), "page_size", 50, 0, 1000);
    ASSERT_TRUE(value.ok()) << text << ": " << value.status();
    EXPECT_EQ(*value, expected) << text;
  }
}

// Out of range, not a number, empty or overflowing: refused naming the parameter and the range,
// never clamped or replaced by the fallback.
TEST(QueryParamsTest, IntParamRefusesWhatIsNotAnIntegerInRange) {
  for (const char* text : {"1001", "-1", "", "ten", "5x", "1.5", "0x10", "99999999999999999999"}) {
    const absl::StatusOr<int64_t> value =
        IntParam(WithQuery({{"page_size", text}}), "page_size", 50, 0, 1000);
    ASSERT_FALSE(value.ok()) << text;
    EXPECT_EQ(value.status().code(), absl::StatusCode::kInvalidArgument) << text;
    EXPECT_THAT(value.status().message(), HasSubstr(std::string("page_size=") + text));
    EXPECT_THAT(value.status().message(), HasSubstr("from 0 to 1000"));
  }
}

TEST(QueryParamsTest, ViewParamTakesTheEnumsNames) {
  EXPECT_EQ(*ViewParam(WithQuery({})), v1::JOB_VIEW_UNSPECIFIED);
  EXPECT_EQ(*ViewParam(WithQuery({{"view", "BASIC"}})), v1::BASIC);
  EXPECT_EQ(*ViewParam(WithQuery({{"view", "FULL"}})), v1::FULL);
}

// Only a view that says something: the unspecified name, numbers, other spellings and an
// empty value are mistakes a client should hear about.
TEST(QueryParamsTest, ViewParamRefusesAnythingElse) {
  for (const char* text : {"JOB_VIEW_UNSPECIFIED", "full", "2", "", "FULL "}) {
    const absl::StatusOr<v1::JobView> view = ViewParam(WithQuery({{"view", text}}));
    ASSERT_FALSE(view.ok()) << text;
    EXPECT_EQ(view.status().code(), absl::StatusCode::kInvalidArgument);
    EXPECT_THAT(view.status().message(), HasSubstr("BASIC or FULL"));
  }
}

TEST(QueryParamsTest, StateParamTakesEveryStatesName) {
  EXPECT_EQ(*StateParam(WithQuery({})), v1::JOB_STATE_UNSPECIFIED);
  for (const v1::JobState state :
       {v1::QUEUED, v1::RUNNING, v1::SUCCEEDED, v1::FAILED, v1::CANCELLED}) {
    const absl::StatusOr<v1::JobState> parsed =
        StateParam(WithQuery({{"state", v1::JobState_Name(state)}}));
    ASSERT_TRUE(parsed.ok()) << v1::JobState_Name(state);
    EXPECT_EQ(*parsed, state);
  }
}

TEST(QueryParamsTest, StateParamRefusesAnythingElse) {
  for (const char* text : {"JOB_STATE_UNSPECIFIED", "queued", "1", "", "DONE"}) {
    const absl::StatusOr<v1::JobState> state = StateParam(WithQuery({{"state", text}}));
    ASSERT_FALSE(state.ok()) << text;
    EXPECT_EQ(state.status().code(), absl::StatusCode::kInvalidArgument);
    EXPECT_THAT(state.status().message(), HasSubstr(std::string("state=") + text + " is not"));
  }
}

}  // namespace
}  // namespace ispq::server::http
