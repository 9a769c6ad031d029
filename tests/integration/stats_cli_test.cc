// SPDX-License-Identifier: Apache-2.0
// The `ispq stats` command as a user runs it: the real binary, its output and exit codes.
#include <fstream>
#include <string>

#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "tests/support/run_command.h"
#include "tests/support/test_data.h"

namespace ispq {
namespace {

using ::testing::HasSubstr;

testing::CommandResult RunIspq(const std::string& args) {
  return testing::RunCommand(std::string(ISPQ_CLI_PATH) + " " + args);
}

TEST(StatsCliTest, PrintsJsonCounts) {
  const testing::CommandResult r =
      RunIspq("stats " + testing::RealTMeshPath("hex-me/s01c_cube.tmesh.json") + " --json");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_THAT(r.output, HasSubstr("\"blocks\":1"));
  EXPECT_THAT(r.output, HasSubstr("\"patches\":6"));
  EXPECT_THAT(r.output, HasSubstr("\"arcs\":12"));
  EXPECT_THAT(r.output, HasSubstr("\"nodes\":8"));
  EXPECT_THAT(r.output, HasSubstr("\"bundles\":3"));
  EXPECT_THAT(r.output, HasSubstr("\"subproblems\":3"));
}

TEST(StatsCliTest, PrintsHumanReadableCounts) {
  const testing::CommandResult r =
      RunIspq("stats " + testing::RealTMeshPath("hex-me/s07c_notch.tmesh.json"));
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_THAT(r.output, HasSubstr("bundles"));
  EXPECT_THAT(r.output, HasSubstr("s07c_notch"));
}

TEST(StatsCliTest, InvalidFileExitsWithValidatorMessage) {
  const std::string path = ::testing::TempDir() + "/broken.tmesh.json";
  std::ifstream in(testing::RealTMeshPath("hex-me/s01c_cube.tmesh.json"));
  std::string json((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  json.replace(json.find("\"length\":"), 9, "\"length\":-");  // a negative length on arc 0
  std::ofstream(path) << json;
  const testing::CommandResult r = RunIspq("stats " + path);
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_THAT(r.output, HasSubstr("arc 0: length -"));
}

TEST(StatsCliTest, UsageErrors) {
  EXPECT_EQ(RunIspq("").exit_code, 2);
  EXPECT_EQ(RunIspq("stats").exit_code, 2);
  EXPECT_EQ(RunIspq("frobnicate x").exit_code, 2);
  EXPECT_EQ(RunIspq("stats /nonexistent.tmesh.json").exit_code, 3);
}

}  // namespace
}  // namespace ispq
