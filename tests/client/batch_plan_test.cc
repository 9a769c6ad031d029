// SPDX-License-Identifier: Apache-2.0
#include "client/batch_plan.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <string>
#include <vector>

#include "absl/strings/match.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "tests/client/client_test_files.h"

namespace ispq::cli {
namespace {

using ::testing::ElementsAre;
using ::testing::HasSubstr;
using ::testing::StartsWith;

v1::QuantizationOptions AtLevel(int level) {
  v1::QuantizationOptions options;
  options.mutable_scaling()->set_level_percent(level);
  return options;
}

std::vector<std::string> Names(const std::vector<BatchJob>& jobs) {
  std::vector<std::string> names;
  for (const BatchJob& job : jobs) names.push_back(job.name);
  return names;
}

TEST(BatchPlanTest, DirectoriesAreSearchedAndResultFilesMirrorThem) {
  testing::TestFolder folder;
  folder.Write("b.tmesh.json", "{}");
  std::filesystem::create_directories(folder.Path("sub/deeper"));
  folder.Write("sub/deeper/a.tmesh.pb", "");
  folder.Write("sub/notes.txt", "not a mesh");
  folder.Write("c.tmesh.binpb", "");
  const absl::StatusOr<std::vector<BatchJob>> jobs =
      PlanBatch({folder.Path("")}, {AtLevel(5), AtLevel(100)}, "/out");
  ASSERT_TRUE(jobs.ok()) << jobs.status();
  // By mesh name, then in the order of the variants (L5 before L100, not as text).
  EXPECT_THAT(Names(*jobs), ElementsAre("b L5", "b L100", "c L5", "c L100", "sub/deeper/a L5",
                                        "sub/deeper/a L100"));
  EXPECT_EQ((*jobs)[4].result_path, "/out/sub/deeper/a.L5.result.json");
  EXPECT_EQ((*jobs)[4].mesh_path, folder.Path("sub/deeper/a.tmesh.pb"));
  EXPECT_EQ((*jobs)[5].options.scaling().level_percent(), 100);
}

TEST(BatchPlanTest, AFileGivenByItselfIsNamedByItsFileName) {
  testing::TestFolder folder;
  const std::string path = folder.Write("part.tmesh.json", "{}");
  v1::QuantizationOptions factor;
  factor.mutable_scaling()->set_factor(2.5);
  const absl::StatusOr<std::vector<BatchJob>> jobs = PlanBatch({path}, {factor}, "out");
  ASSERT_TRUE(jobs.ok()) << jobs.status();
  EXPECT_THAT(Names(*jobs), ElementsAre("part s2.5"));
  EXPECT_EQ((*jobs)[0].result_path, "out/part.s2.5.result.json");
}

TEST(BatchPlanTest, BadInputsAreNamed) {
  testing::TestFolder folder;
  const std::string other = folder.Write("part.obj", "");
  absl::StatusOr<std::vector<BatchJob>> jobs = PlanBatch({other}, {AtLevel(5)}, "out");
  EXPECT_EQ(jobs.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(jobs.status().message()), StartsWith(other + ": not a T-mesh file"));

  std::filesystem::create_directories(folder.Path("empty"));
  jobs = PlanBatch({folder.Path("empty")}, {AtLevel(5)}, "out");
  EXPECT_THAT(std::string(jobs.status().message()), HasSubstr("no T-mesh files in it"));

  jobs = PlanBatch({folder.Path("missing.tmesh.json")}, {AtLevel(5)}, "out");
  EXPECT_EQ(jobs.status().code(), absl::StatusCode::kInvalidArgument);
}

TEST(BatchPlanTest, TwoInputsWritingTheSameResultFileAreRefused) {
  testing::TestFolder folder;
  std::filesystem::create_directories(folder.Path("x"));
  std::filesystem::create_directories(folder.Path("y"));
  const std::string first = folder.Write("x/part.tmesh.json", "{}");
  const std::string second = folder.Write("y/part.tmesh.pb", "");
  const absl::StatusOr<std::vector<BatchJob>> jobs =
      PlanBatch({first, second}, {AtLevel(5)}, "out");
  EXPECT_EQ(jobs.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(jobs.status().message()),
              HasSubstr("both would write out/part.L5.result.json"));
}

TEST(BatchPlanTest, ScalingLabels) {
  v1::Scaling scaling;
  EXPECT_EQ(ScalingLabel(scaling), "default");
  scaling.set_level_percent(17);
  EXPECT_EQ(ScalingLabel(scaling), "L17");
  scaling.set_factor(0.25);
  EXPECT_EQ(ScalingLabel(scaling), "s0.25");
  scaling.set_target_hexes(10000);
  EXPECT_EQ(ScalingLabel(scaling), "h10000");
}

// The id must be the same for the same request and result file (a retried or resumed batch gets
// its job back), different otherwise, and acceptable to the server (AIP-155: <= 64 characters of
// [A-Za-z0-9_-]).
TEST(BatchPlanTest, RequestIdsAreStableAndTellRequestsApart) {
  v1::QuantizeRequest request;
  *request.mutable_mesh() = testing::TwoBlockMesh();
  *request.mutable_options() = AtLevel(25);
  const std::string id = BatchRequestId(request, "/out/a.L25.result.json");
  EXPECT_EQ(BatchRequestId(request, "/out/a.L25.result.json"), id);
  EXPECT_LE(id.size(), 64u);
  EXPECT_TRUE(std::all_of(id.begin(), id.end(), [](char c) {
    return std::isalnum(c) || c == '-' || c == '_';
  })) << id;
  v1::QuantizeRequest with_id = request;
  with_id.set_request_id(id);
  EXPECT_EQ(BatchRequestId(with_id, "/out/a.L25.result.json"), id) << "the id is not its own input";
  EXPECT_NE(BatchRequestId(request, "/elsewhere/a.L25.result.json"), id);
  v1::QuantizeRequest other = request;
  *other.mutable_options() = AtLevel(50);
  EXPECT_NE(BatchRequestId(other, "/out/a.L25.result.json"), id);
  other = request;
  other.mutable_mesh()->mutable_arcs(0)->set_length(request.mesh().arcs(0).length() + 1);
  EXPECT_NE(BatchRequestId(other, "/out/a.L25.result.json"), id);
}

}  // namespace
}  // namespace ispq::cli
