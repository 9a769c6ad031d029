// SPDX-License-Identifier: Apache-2.0
// `ispq validate`: the grid's own lengths are a valid quantization (exit 0, objective against the
// chosen scaling, hex count); one arc changed makes it NOT valid (exit 4) with the problems
// named, in text and in the JSON verdict; a result with the wrong number of arcs or an
// unreadable file exits with 3, an unusable scaling with 2.
#include "client/validate_command.h"

#include <string>
#include <vector>

#include "client/exit_codes.h"
#include "client/message_json.h"
#include "core/quantization_validator.h"
#include "gmock/gmock.h"
#include "google/protobuf/util/json_util.h"
#include "gtest/gtest.h"
#include "tests/client/client_test_files.h"
#include "tests/support/test_data.h"

namespace ispq::cli {
namespace {

using ::testing::HasSubstr;
using ::testing::StartsWith;

struct CommandRun {
  int exit_code;
  std::string out, err;
};

CommandRun Validate(const ValidateCommandOptions& options) {
  ::testing::internal::CaptureStdout();
  ::testing::internal::CaptureStderr();
  const int exit_code = RunValidate(options);
  std::string out = ::testing::internal::GetCapturedStdout();
  return {exit_code, out, ::testing::internal::GetCapturedStderr()};
}

class ValidateCommandTest : public ::testing::Test {
 protected:
  ValidateCommandTest() {
    options_.mesh_path = folder_.Write("m.pb", testing::TwoBlockMesh().SerializeAsString());
    options_.scaling.set_factor(2);
  }

  // Writes a result file with `q` and points the options at it.
  void UseResult(const std::vector<int64_t>& q) {
    v1::QuantizationResult result = testing::GridResult();
    result.clear_q();
    for (int64_t value : q) result.add_q(static_cast<int32_t>(value));
    options_.result_path = folder_.Write("result.json", MessageToJson(result));
  }

  // q with the first arc along u doubled: the patches on it no longer have equal opposite sides.
  std::vector<int64_t> BrokenQ() const {
    std::vector<int64_t> q = testing::GridQ();
    q[0] = 2;
    return q;
  }

  testing::TestFolder folder_;
  ValidateCommandOptions options_;
};

TEST_F(ValidateCommandTest, TheGridsOwnLengthsAreValid) {
  const TMesh mesh = testing::TMeshOrDie(testing::TwoBlockMesh());
  ASSERT_TRUE(ValidateQuantization(mesh, testing::GridQ())->valid());
  UseResult(testing::GridQ());
  const CommandRun run = Validate(options_);
  EXPECT_EQ(run.exit_code, kExitOk) << run.err;
  // 20 arcs of length 1 against targets of 2: objective 20; two unit blocks.
  EXPECT_EQ(run.out, "valid: objective 20, 2 hexes\n");
}

TEST_F(ValidateCommandTest, AnInconsistentQIsNotValidAndItsProblemsAreNamed) {
  const TMesh mesh = testing::TMeshOrDie(testing::TwoBlockMesh());
  const absl::StatusOr<ValidationReport> report = ValidateQuantization(mesh, BrokenQ());
  ASSERT_TRUE(report.ok());
  ASSERT_FALSE(report->valid());
  UseResult(BrokenQ());
  const CommandRun text = Validate(options_);
  EXPECT_EQ(text.exit_code, kExitInvalidResult);
  EXPECT_THAT(text.out, StartsWith("NOT valid: objective "));
  EXPECT_THAT(text.out, HasSubstr(report->Describe()));

  options_.json = true;
  const CommandRun json = Validate(options_);
  EXPECT_EQ(json.exit_code, kExitInvalidResult);
  v1::ValidationVerdict verdict;
  ASSERT_TRUE(google::protobuf::util::JsonStringToMessage(json.out, &verdict).ok()) << json.out;
  EXPECT_FALSE(verdict.valid());
  EXPECT_EQ(verdict.hexes(), 0);
  EXPECT_EQ(verdict.consistency_violations(), static_cast<int>(report->consistency.size()));
  EXPECT_GT(verdict.consistency_violations(), 0);
  EXPECT_GT(verdict.problems_size(), 0);
}

TEST_F(ValidateCommandTest, AResultForAnotherMeshIsInvalidInput) {
  std::vector<int64_t> q = testing::GridQ();
  q.pop_back();
  UseResult(q);
  const CommandRun run = Validate(options_);
  EXPECT_EQ(run.exit_code, kExitInvalidInput);
  EXPECT_THAT(run.err, StartsWith("ispq: " + options_.result_path +
                                  ": the result has 19 arc "
                                  "lengths but the mesh has 20 arcs"));
  EXPECT_EQ(run.out, "");
}

TEST_F(ValidateCommandTest, UnreadableFilesAreInvalidInputAndABadScalingIsUsage) {
  options_.result_path = folder_.Write("result.json", "[1, 2");
  EXPECT_EQ(Validate(options_).exit_code, kExitInvalidInput);
  UseResult(testing::GridQ());
  ValidateCommandOptions missing_mesh = options_;
  missing_mesh.mesh_path = folder_.Path("missing.pb");
  EXPECT_EQ(Validate(missing_mesh).exit_code, kExitInvalidInput);
  options_.scaling.set_level_percent(3);  // not one of the format's levels
  const CommandRun run = Validate(options_);
  EXPECT_EQ(run.exit_code, kExitUsage);
  EXPECT_THAT(run.err, StartsWith("ispq: "));
}

}  // namespace
}  // namespace ispq::cli
