// SPDX-License-Identifier: Apache-2.0
// Result files and the summary: a written result reads back equal, unknown keys in a result
// produced elsewhere are ignored, unreadable files are refused naming the file, the summary
// shows the optional lines only when they have something to say, and OutputResult's exit code
// follows the result (0 valid, 4 invalid) or the failed write (5).
#include "client/result_output.h"

#include <sstream>
#include <string>

#include "client/exit_codes.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "tests/client/client_test_files.h"

namespace ispq::cli {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;

std::string Summary(const v1::QuantizationResult& result) {
  std::ostringstream out;
  PrintResultSummary(result, out);
  return out.str();
}

TEST(ResultOutputTest, AWrittenResultReadsBackEqual) {
  const testing::TestFolder folder;
  v1::QuantizationResult result = testing::GridResult();
  result.set_lower_bound(0.5);
  result.mutable_stats()->set_greedy_seconds(0.25);
  const std::string path = folder.Path("result.json");
  ASSERT_TRUE(WriteResultFile(path, result).ok());
  const absl::StatusOr<v1::QuantizationResult> read = ReadResultFile(path);
  ASSERT_TRUE(read.ok()) << read.status();
  EXPECT_EQ(read->SerializeAsString(), result.SerializeAsString());
}

TEST(ResultOutputTest, UnknownKeysAreIgnored) {
  const testing::TestFolder folder;
  const std::string path =
      folder.Write("other.json", R"({"q": [1, 2], "valid": true, "producedBy": "elsewhere"})");
  const absl::StatusOr<v1::QuantizationResult> read = ReadResultFile(path);
  ASSERT_TRUE(read.ok()) << read.status();
  EXPECT_EQ(read->q_size(), 2);
  EXPECT_TRUE(read->valid());
}

TEST(ResultOutputTest, UnreadableFilesAreRefusedNamingTheFile) {
  const testing::TestFolder folder;
  const std::string garbage = folder.Write("garbage.json", "{\"q\": [1,");
  const absl::StatusOr<v1::QuantizationResult> parsed = ReadResultFile(garbage);
  EXPECT_EQ(parsed.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(parsed.status().message()),
              HasSubstr(garbage + ": not a quantization result"));
  const std::string missing = folder.Path("missing.json");
  EXPECT_EQ(ReadResultFile(missing).status().code(), absl::StatusCode::kNotFound);
  const absl::Status unwritable = WriteResultFile(folder.Path("no/such/dir.json"), {});
  EXPECT_EQ(unwritable.code(), absl::StatusCode::kInternal);
  EXPECT_THAT(std::string(unwritable.message()), HasSubstr("no/such/dir.json: cannot write"));
}

TEST(ResultOutputTest, TheSummaryShowsOptionalLinesOnlyWhenTheyApply) {
  v1::QuantizationResult result = testing::GridResult();
  result.set_objective(1.5);
  const std::string plain = Summary(result);
  EXPECT_THAT(plain, HasSubstr("valid quantization of two-blocks at scaling 1 (CONVERGED)"));
  EXPECT_THAT(plain, HasSubstr("objective 1.5, 2 hexes, 20 arcs"));
  EXPECT_THAT(plain, Not(HasSubstr("lower bound")));
  EXPECT_THAT(plain, Not(HasSubstr("greedy checks answered")));
  EXPECT_THAT(plain, Not(HasSubstr("exact:")));

  result.set_valid(false);
  result.set_lower_bound(1.2);
  result.set_gap(0.2);
  result.mutable_stats()->set_covered_checks(3);
  result.mutable_stats()->set_milp_solves(2);
  result.mutable_stats()->set_milp_nodes(40);
  const std::string full = Summary(result);
  EXPECT_THAT(full, HasSubstr("NOT valid quantization of two-blocks"));
  EXPECT_THAT(full, HasSubstr("lower bound 1.2, gap 20 %"));
  EXPECT_THAT(full, HasSubstr("3 greedy checks answered by another root's sheet"));
  EXPECT_THAT(full, HasSubstr("exact: 2 MILP solves, 40 nodes"));
}

TEST(ResultOutputTest, OutputResultWritesTheFileAndReturnsTheVerdictsExitCode) {
  const testing::TestFolder folder;
  const std::string path = folder.Path("out.json");
  ::testing::internal::CaptureStdout();
  EXPECT_EQ(OutputResult(testing::GridResult(), path, /*json=*/true), kExitOk);
  const std::string json = ::testing::internal::GetCapturedStdout();
  EXPECT_THAT(json, HasSubstr("\"valid\":true"));
  const absl::StatusOr<v1::QuantizationResult> written = ReadResultFile(path);
  ASSERT_TRUE(written.ok());
  EXPECT_EQ(written->SerializeAsString(), testing::GridResult().SerializeAsString());

  v1::QuantizationResult invalid = testing::GridResult();
  invalid.set_valid(false);
  ::testing::internal::CaptureStdout();
  EXPECT_EQ(OutputResult(invalid, "", /*json=*/false), kExitInvalidResult);
  EXPECT_THAT(::testing::internal::GetCapturedStdout(), HasSubstr("NOT valid quantization"));

  ::testing::internal::CaptureStdout();
  ::testing::internal::CaptureStderr();
  EXPECT_EQ(OutputResult(testing::GridResult(), folder.Path("no/such/dir.json"), false),
            kExitFailed);
  EXPECT_EQ(::testing::internal::GetCapturedStdout(), "");  // nothing shown when the write fails
  EXPECT_THAT(::testing::internal::GetCapturedStderr(), HasSubstr("ispq: "));
}

}  // namespace
}  // namespace ispq::cli
