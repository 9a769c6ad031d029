// SPDX-License-Identifier: Apache-2.0
#include "server/http/proto_json.h"

#include <string>

#include "absl/status/status.h"
#include "gmock/gmock.h"
#include "google/protobuf/util/message_differencer.h"
#include "gtest/gtest.h"
#include "ispq/v1/service.pb.h"

namespace ispq::server::http {
namespace {

using ::google::protobuf::util::MessageDifferencer;
using ::testing::HasSubstr;
using ::testing::Not;

TEST(ProtoJsonTest, PrintsCamelCaseNamesEnumNamesAndInt64AsStrings) {
  v1::Job job;
  job.set_name("jobs/abc");
  job.set_state(v1::RUNNING);
  job.set_event_count(int64_t{1} << 53 | 1);  // beyond a JavaScript number's precision
  const std::string json = ToJson(job);
  EXPECT_THAT(json, HasSubstr("\"name\":\"jobs/abc\""));
  EXPECT_THAT(json, HasSubstr("\"state\":\"RUNNING\""));
  EXPECT_THAT(json, HasSubstr("\"eventCount\":\"9007199254740993\""));
  EXPECT_THAT(json, Not(HasSubstr("event_count")));
}

// As the CLI's result files: a field at its default is printed, not left out, so that a client
// reading `done` or `scaling` finds it.
TEST(ProtoJsonTest, PrintsFieldsAtTheirDefaults) {
  const std::string json = ToJson(v1::Job());
  EXPECT_THAT(json, HasSubstr("\"done\":false"));
  EXPECT_THAT(json, HasSubstr("\"scaling\":0"));
  EXPECT_THAT(json, HasSubstr("\"eventCount\":\"0\""));
  EXPECT_THAT(json, HasSubstr("\"state\":\"JOB_STATE_UNSPECIFIED\""));
  EXPECT_THAT(json, HasSubstr("\"name\":\"\""));
}

// One event is one SSE `data:` line: a newline inside would end it early.
TEST(ProtoJsonTest, PrintsOneLineWhateverTheStringsHold) {
  v1::QuantizeEvent event;
  event.set_job("jobs/a");
  event.mutable_error()->set_message("line one\nline two\r\n");
  const std::string json = ToJson(event);
  EXPECT_EQ(json.find('\n'), std::string::npos) << json;
  EXPECT_EQ(json.find('\r'), std::string::npos) << json;
  EXPECT_THAT(json, HasSubstr("line one\\nline two\\r\\n"));
}

TEST(ProtoJsonTest, ConvertsJsonToTheBinaryFormWithEitherSpellingOfNames) {
  v1::ListJobsRequest expected;
  expected.set_page_size(25);
  expected.set_page_token("next");
  for (const char* json :
       {R"({"pageSize": 25, "pageToken": "next"})", R"({"page_size": 25, "page_token": "next"})",
        R"({"pageSize": "25", "pageToken": "next"})"}) {
    const absl::StatusOr<std::string> binary =
        JsonToBinary(*v1::ListJobsRequest::descriptor(), json);
    ASSERT_TRUE(binary.ok()) << json << ": " << binary.status();
    v1::ListJobsRequest parsed;
    ASSERT_TRUE(parsed.ParseFromString(*binary));
    EXPECT_TRUE(MessageDifferencer::Equals(parsed, expected))
        << json << ": " << parsed.DebugString();
  }
}

// What the server prints it can read back: a client may resubmit a job's request as it got it.
TEST(ProtoJsonTest, WhatIsPrintedConvertsBackToTheSameMessage) {
  v1::QuantizeRequest request;
  request.set_stored_mesh("meshes/m1");
  request.set_request_id("retry-1");
  request.mutable_options()->set_per_arc_nonnegative(true);
  request.mutable_options()->set_decompose(false);
  request.mutable_options()->mutable_time_limit()->set_seconds(90);
  request.mutable_progress_interval()->set_nanos(250'000'000);
  const absl::StatusOr<std::string> binary =
      JsonToBinary(*v1::QuantizeRequest::descriptor(), ToJson(request));
  ASSERT_TRUE(binary.ok()) << binary.status();
  v1::QuantizeRequest parsed;
  ASSERT_TRUE(parsed.ParseFromString(*binary));
  EXPECT_TRUE(MessageDifferencer::Equals(parsed, request)) << parsed.DebugString();
  EXPECT_TRUE(parsed.options().has_decompose());  // an explicit false survives
}

TEST(ProtoJsonTest, RefusesWhatIsNotTheTypeInJson) {
  for (const char* json : {
           R"({"pageSize": 25, "unknownField": 1})",  // an unknown field
           R"({"pageSize": "many"})",                 // a value of the wrong type
           R"({"pageSize": 1.5})",                    // not an integer
           R"({"pageSize": 25)",                      // malformed
           R"([{"pageSize": 25}])",                   // not an object
           "",
       }) {
    const absl::StatusOr<std::string> binary =
        JsonToBinary(*v1::ListJobsRequest::descriptor(), json);
    ASSERT_FALSE(binary.ok()) << json;
    EXPECT_EQ(binary.status().code(), absl::StatusCode::kInvalidArgument) << json;
    EXPECT_THAT(binary.status().message(),
                HasSubstr("the body is not a ispq.v1.ListJobsRequest in JSON: "));
  }
}

TEST(ProtoJsonTest, NamesTheUnknownField) {
  const absl::StatusOr<std::string> binary =
      JsonToBinary(*v1::ListJobsRequest::descriptor(), R"({"pageSise": 10})");
  ASSERT_FALSE(binary.ok());
  EXPECT_THAT(binary.status().message(), HasSubstr("pageSise"));
}

}  // namespace
}  // namespace ispq::server::http
