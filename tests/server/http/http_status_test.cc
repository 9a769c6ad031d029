// SPDX-License-Identifier: Apache-2.0
#include "server/http/http_status.h"

#include <optional>
#include <string>

#include "absl/status/status.h"
#include "absl/time/time.h"
#include "google/protobuf/struct.pb.h"
#include "google/protobuf/util/json_util.h"
#include "gtest/gtest.h"
#include "server/jobs/retry_hint.h"

namespace ispq::server::http {
namespace {

google::protobuf::Struct ParseJson(const std::string& json) {
  google::protobuf::Struct parsed;
  EXPECT_TRUE(google::protobuf::util::JsonStringToMessage(json, &parsed).ok()) << json;
  return parsed;
}

// The google.api HTTP mapping of every gRPC code, which clients and proxies rely on.
TEST(HttpStatusTest, MapsEveryGrpcCodeAsGoogleApiDoes) {
  const struct {
    absl::StatusCode code;
    int http;
  } kMapping[] = {
      {absl::StatusCode::kOk, 200},
      {absl::StatusCode::kCancelled, 499},
      {absl::StatusCode::kUnknown, 500},
      {absl::StatusCode::kInvalidArgument, 400},
      {absl::StatusCode::kDeadlineExceeded, 504},
      {absl::StatusCode::kNotFound, 404},
      {absl::StatusCode::kAlreadyExists, 409},
      {absl::StatusCode::kPermissionDenied, 403},
      {absl::StatusCode::kResourceExhausted, 429},
      {absl::StatusCode::kFailedPrecondition, 400},
      {absl::StatusCode::kAborted, 409},
      {absl::StatusCode::kOutOfRange, 400},
      {absl::StatusCode::kUnimplemented, 501},
      {absl::StatusCode::kInternal, 500},
      {absl::StatusCode::kUnavailable, 503},
      {absl::StatusCode::kDataLoss, 500},
      {absl::StatusCode::kUnauthenticated, 401},
  };
  for (const auto& [code, http] : kMapping) {
    EXPECT_EQ(HttpStatusCode(code), http) << absl::StatusCodeToString(code);
    EXPECT_EQ(HttpStatusOf(absl::Status(code, "x")), http) << absl::StatusCodeToString(code);
  }
}

TEST(HttpStatusTest, AnAttachedHttpStatusOverridesTheCodesMappingAndKeepsTheStatus) {
  const absl::Status plain = absl::ResourceExhaustedError("the body is too large");
  const absl::Status refused = WithHttpStatus(plain, 413);
  EXPECT_EQ(HttpStatusOf(plain), 429);
  EXPECT_EQ(HttpStatusOf(refused), 413);
  EXPECT_EQ(refused.code(), absl::StatusCode::kResourceExhausted);
  EXPECT_EQ(refused.message(), "the body is too large");
  // The body still names the gRPC code, not the HTTP one.
  const google::protobuf::Struct body = ParseJson(ErrorJson(refused));
  EXPECT_EQ(body.fields().at("code").number_value(), 8);
  EXPECT_EQ(body.fields().at("status").string_value(), "RESOURCE_EXHAUSTED");
}

TEST(HttpStatusTest, ErrorJsonCarriesCodeNumberNameAndMessage) {
  const google::protobuf::Struct body =
      ParseJson(ErrorJson(absl::InvalidArgumentError("page_size must be at most 1000")));
  ASSERT_EQ(body.fields().size(), 3u);
  EXPECT_EQ(body.fields().at("code").number_value(), 3);
  EXPECT_EQ(body.fields().at("status").string_value(), "INVALID_ARGUMENT");
  EXPECT_EQ(body.fields().at("message").string_value(), "page_size must be at most 1000");
}

// A message that quotes the client's input must not break (or inject into) the JSON.
TEST(HttpStatusTest, ErrorJsonEscapesTheMessage) {
  const std::string hostile = "bad \"name\": {\"code\": 0}\n\\ \x01 caf\xC3\xA9";
  const std::string json = ErrorJson(absl::NotFoundError(hostile));
  EXPECT_EQ(json.find('\n'), std::string::npos);
  const google::protobuf::Struct body = ParseJson(json);
  EXPECT_EQ(body.fields().at("message").string_value(), hostile);
  EXPECT_EQ(body.fields().at("code").number_value(), 5);
}

TEST(HttpStatusTest, RetryAfterIsTheHintInWholeSecondsRoundedUpAndAtLeastOne) {
  EXPECT_EQ(RetryAfterSeconds(absl::ResourceExhaustedError("full")), std::nullopt);
  EXPECT_EQ(RetryAfterSeconds(absl::OkStatus()), std::nullopt);
  EXPECT_EQ(RetryAfterSeconds(ResourceExhaustedWithRetryHint("full", absl::ZeroDuration())), "1");
  EXPECT_EQ(RetryAfterSeconds(ResourceExhaustedWithRetryHint("full", absl::Milliseconds(1))), "1");
  EXPECT_EQ(RetryAfterSeconds(ResourceExhaustedWithRetryHint("full", absl::Seconds(3))), "3");
  EXPECT_EQ(RetryAfterSeconds(ResourceExhaustedWithRetryHint("full", absl::Milliseconds(3001))),
            "4");
  EXPECT_EQ(RetryAfterSeconds(ResourceExhaustedWithRetryHint("full", absl::Minutes(2))), "120");
}

}  // namespace
}  // namespace ispq::server::http
