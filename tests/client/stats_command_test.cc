// SPDX-License-Identifier: Apache-2.0
// `ispq stats`: the JSON form is the mesh's MeshStats message, the text form shows the same
// counts under the file's path and mesh name, and a bad file exits with 3.
#include "client/stats_command.h"

#include <string>

#include "client/exit_codes.h"
#include "core/mesh_stats.h"
#include "core/proto/mesh_stats_proto.h"
#include "gmock/gmock.h"
#include "google/protobuf/util/json_util.h"
#include "gtest/gtest.h"
#include "tests/client/client_test_files.h"
#include "tests/support/test_data.h"

namespace ispq::cli {
namespace {

using ::testing::HasSubstr;
using ::testing::StartsWith;

TEST(StatsCommandTest, JsonIsTheMeshStatsMessage) {
  const testing::TestFolder folder;
  const std::string path = folder.Write("m.pb", testing::TwoBlockMesh().SerializeAsString());
  ::testing::internal::CaptureStdout();
  EXPECT_EQ(RunStatsCommand(path, /*json=*/true), kExitOk);
  const std::string json = ::testing::internal::GetCapturedStdout();
  v1::MeshStats printed;
  ASSERT_TRUE(google::protobuf::util::JsonStringToMessage(json, &printed).ok()) << json;
  const v1::MeshStats expected =
      MeshStatsToProto(ComputeMeshStats(testing::TMeshOrDie(testing::TwoBlockMesh())));
  EXPECT_EQ(printed.SerializeAsString(), expected.SerializeAsString());
  EXPECT_EQ(printed.blocks(), 2);
}

TEST(StatsCommandTest, TextShowsTheCountsUnderThePathAndName) {
  const testing::TestFolder folder;
  const std::string path = folder.Write("m.pb", testing::TwoBlockMesh().SerializeAsString());
  ::testing::internal::CaptureStdout();
  EXPECT_EQ(RunStatsCommand(path, /*json=*/false), kExitOk);
  const std::string text = ::testing::internal::GetCapturedStdout();
  const MeshStats stats = ComputeMeshStats(testing::TMeshOrDie(testing::TwoBlockMesh()));
  EXPECT_THAT(text, StartsWith(path + " (two-blocks)\n"));
  EXPECT_THAT(text, HasSubstr("  blocks            2\n"));
  EXPECT_THAT(text, HasSubstr("  arcs              " + std::to_string(stats.arcs) + "\n"));
  EXPECT_THAT(text, HasSubstr("  critical          " + std::to_string(stats.critical_nodes) +
                              " nodes, " + std::to_string(stats.critical_arcs) + " arcs, " +
                              std::to_string(stats.critical_patches) + " patches\n"));
}

TEST(StatsCommandTest, ABadFileExitsWithInvalidInput) {
  const testing::TestFolder folder;
  const std::string path = folder.Path("missing.tmesh.json");
  ::testing::internal::CaptureStdout();
  ::testing::internal::CaptureStderr();
  EXPECT_EQ(RunStatsCommand(path, /*json=*/true), kExitInvalidInput);
  EXPECT_EQ(::testing::internal::GetCapturedStdout(), "");
  EXPECT_EQ(::testing::internal::GetCapturedStderr(), "ispq: " + path + ": cannot open file\n");
}

}  // namespace
}  // namespace ispq::cli
