// SPDX-License-Identifier: Apache-2.0
// Exact mode through the service and the CLI: a job with METHOD_EXACT on the real server streams
// progress with the running bound and improving intermediate quantizations and ends OPTIMAL with
// a valid result better than ISP's; `ispq quantize --method exact` does the same from the command
// line, in-process and remotely.
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "core/proto/quantization_proto.h"
#include "core/quantizer.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "tests/integration/service_test_support.h"
#include "tests/support/run_command.h"
#include "tests/support/test_data.h"
#include "tests/support/tmesh_copies.h"

namespace ispq::testing {
namespace {

using ::testing::HasSubstr;

// n06u_anti_pentapyr at scaling factor 2: small, and exact mode improves on ISP there (26.55
// against 26.97 per copy; ISP is optimal at every one of the real set's levels).
constexpr char kModel[] = "n06u_anti_pentapyr";
constexpr double kFactor = 2;
// Six disjoint copies: 1878 arcs. From 2000 arcs on (IspTuning::layered_start_min_arcs) ISP
// descends from the layered start, and then it finds the optimum itself on copies of every real
// mesh at factors 1, 2 and 3 (30 copies of this one included), leaving exact mode nothing to
// improve; below, ISP ends at 161.82 and exact mode at the optimum 159.31.
constexpr int kCopies = 6;

double ObjectiveOf(const v1::TMesh& mesh, double scaling, const v1::IntermediateQuantization& q) {
  double objective = 0;
  for (int a = 0; a < mesh.arcs_size(); ++a) {
    const double difference = q.q(a) - scaling * mesh.arcs(a).length();
    objective += difference * difference;
  }
  return objective;
}

TEST(ExactJobTest, StreamsTheBoundAndImprovementsAndEndsOptimal) {
  const v1::TMesh mesh = DisjointCopies(RealMeshNamed(kModel), kCopies);
  std::unique_ptr<ServerProcess> server = StartServerOrFail({"--workers=1"});
  ASSERT_NE(server, nullptr);
  client::QuantizerClient client = ClientOf(*server);
  v1::QuantizeRequest request = RequestFor(mesh, 100);
  request.mutable_options()->mutable_scaling()->set_factor(kFactor);
  request.mutable_options()->set_method(v1::METHOD_EXACT);
  request.mutable_progress_interval()->set_nanos(10'000'000);
  request.mutable_intermediate_interval()->set_nanos(1'000'000);
  std::vector<v1::QuantizeEvent> events;
  const client::JobOutcome outcome =
      client.Quantize(request, StreamFor(kJobTimeout, [&events](const v1::QuantizeEvent& event) {
                        events.push_back(event);
                        return true;
                      }));
  ASSERT_TRUE(outcome.status.ok()) << outcome.status << "\n" << server->Log();
  ASSERT_TRUE(outcome.result.has_value());
  EXPECT_TRUE(IsValidResult(mesh, *outcome.result));
  EXPECT_EQ(outcome.result->termination(), v1::OPTIMAL);
  ASSERT_TRUE(outcome.result->has_lower_bound());
  EXPECT_EQ(outcome.result->lower_bound(), outcome.result->objective());
  EXPECT_EQ(outcome.result->gap(), 0);
  EXPECT_GE(outcome.result->stats().milp_solves(), 1);

  ASSERT_FALSE(events.empty());
  const double scaling = events.front().accepted().scaling();
  int exact_progress = 0;
  std::vector<double> intermediate_objectives;
  for (const v1::QuantizeEvent& event : events) {
    if (event.has_progress() && event.progress().phase() == v1::EXACT) {
      ++exact_progress;
      EXPECT_TRUE(event.progress().has_lower_bound());
      EXPECT_LE(event.progress().lower_bound(), event.progress().objective() + 1e-9);
    }
    if (!event.has_intermediate()) continue;
    const v1::IntermediateQuantization& q = event.intermediate();
    ASSERT_EQ(q.q_size(), mesh.arcs_size());
    EXPECT_NEAR(ObjectiveOf(mesh, scaling, q), q.progress().objective(), 1e-6);
    if (q.progress().separating()) intermediate_objectives.push_back(q.progress().objective());
  }
  EXPECT_GE(exact_progress, 1);
  // Valid intermediate quantizations only ever improve, and the result is at least as good.
  ASSERT_FALSE(intermediate_objectives.empty());
  for (size_t i = 1; i < intermediate_objectives.size(); ++i) {
    EXPECT_LT(intermediate_objectives[i], intermediate_objectives[i - 1]);
  }
  EXPECT_LE(outcome.result->objective(), intermediate_objectives.back() + 1e-9);

  // Better than ISP on this instance (in-process). Whether the MILP's last incumbent is also
  // streamed as an intermediate quantization before the result supersedes it depends on timing
  // (the job takes a quarter of a second), so only the result is held to it.
  v1::QuantizationOptions isp;
  isp.mutable_scaling()->set_factor(kFactor);
  const TMesh core_mesh = TMeshOrDie(mesh);
  const absl::StatusOr<QuantizeResult> local =
      Quantize(core_mesh, *QuantizeOptionsFromProto(isp, core_mesh));
  ASSERT_TRUE(local.ok());
  EXPECT_LT(outcome.result->objective(), local->objective - 1e-3);
}

TEST(ExactJobTest, CommandLineExactModeLocallyAndRemotely) {
  const std::string cli(ISPQ_CLI_PATH);
  const std::string mesh = RealTMeshPath("hex-me/s07c_notch.tmesh.json");
  const CommandResult local =
      RunCommand(cli + " quantize " + mesh + " --local --level 50 --method exact");
  ASSERT_EQ(local.exit_code, 0) << local.output;
  EXPECT_THAT(local.output, HasSubstr("(OPTIMAL)"));
  EXPECT_THAT(local.output, HasSubstr("gap 0 %"));
  EXPECT_THAT(local.output, HasSubstr("progress phase=exact"));
  EXPECT_THAT(local.output, HasSubstr("MILP solves"));

  std::unique_ptr<ServerProcess> server = StartServerOrFail({"--workers=1"});
  ASSERT_NE(server, nullptr);
  const CommandResult remote =
      RunCommand(cli + " quantize " + mesh + " --server " + server->address() +
                 " --level 50 --method exact --progress=false");
  ASSERT_EQ(remote.exit_code, 0) << remote.output;
  EXPECT_THAT(remote.output, HasSubstr("(OPTIMAL)"));

  const CommandResult bad =
      RunCommand(cli + " quantize " + mesh + " --local --level 50 --method fast");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_THAT(bad.output, HasSubstr("--method must be isp or exact"));
}

}  // namespace
}  // namespace ispq::testing
