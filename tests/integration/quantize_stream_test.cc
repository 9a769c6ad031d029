// SPDX-License-Identifier: Apache-2.0
// Quantize (submit and watch in one call) end to end on real T-meshes: the real server binary,
// the real client library, events in order, and results the validator accepts that are the
// same as an in-process solve's.
#include <cmath>
#include <string>
#include <vector>

#include "core/mesh_stats.h"
#include "core/proto/mesh_stats_proto.h"
#include "core/proto/quantization_proto.h"
#include "core/quantizer.h"
#include "gmock/gmock.h"
#include "google/protobuf/util/message_differencer.h"
#include "gtest/gtest.h"
#include "tests/integration/service_test_support.h"
#include "tests/support/test_data.h"

namespace ispq::testing {
namespace {

using ::google::protobuf::util::MessageDifferencer;
using ::testing::ElementsAreArray;
using ::testing::StartsWith;

struct Instance {
  std::string model;  // a real file ("<dataset>/<file>") or a real model's name
  int level;
};

v1::TMesh LoadInstance(const Instance& instance) {
  if (instance.model.ends_with(".tmesh.json")) return LoadProtoOrDie(RealTMeshPath(instance.model));
  return RealMeshNamed(instance.model);
}

// The objective d(q) = sum (q - s l)^2 of an intermediate quantization, from its q.
double ObjectiveOf(const v1::TMesh& mesh, double scaling, const v1::IntermediateQuantization& q) {
  double objective = 0;
  for (int a = 0; a < mesh.arcs_size(); ++a) {
    const double difference = q.q(a) - scaling * mesh.arcs(a).length();
    objective += difference * difference;
  }
  return objective;
}

class QuantizeStreamTest : public ::testing::TestWithParam<Instance> {};

// Checks a stream's intermediate quantizations in order: each is a full q whose reported
// objective is its own, and each improves on the one before (a separating q beats any other,
// then a lower objective wins).
class IntermediateSequenceChecker {
 public:
  IntermediateSequenceChecker(const v1::TMesh& mesh, double scaling)
      : mesh_(mesh), scaling_(scaling) {}

  void Check(const v1::QuantizeEvent& event) {
    const v1::IntermediateQuantization& intermediate = event.intermediate();
    ASSERT_EQ(intermediate.q_size(), mesh_.arcs_size());
    const double objective = intermediate.progress().objective();
    EXPECT_NEAR(ObjectiveOf(mesh_, scaling_, intermediate), objective, 1e-6 * (1 + objective));
    const bool separating = intermediate.progress().separating();
    EXPECT_TRUE((separating && !sent_separating_) ||
                (separating == sent_separating_ && objective < sent_objective_))
        << "intermediate quantization " << event.sequence() << " does not improve";
    sent_separating_ = separating;
    sent_objective_ = objective;
  }

 private:
  const v1::TMesh& mesh_;
  const double scaling_;
  bool sent_separating_ = false;
  double sent_objective_ = INFINITY;
};

TEST_P(QuantizeStreamTest, StreamsEventsInOrderAndAValidResult) {
  const v1::TMesh mesh = LoadInstance(GetParam());
  std::unique_ptr<ServerProcess> server = StartServerOrFail({"--workers=2"});
  ASSERT_NE(server, nullptr);
  client::QuantizerClient client = ClientOf(*server);

  v1::QuantizeRequest request = RequestFor(mesh, GetParam().level);
  request.mutable_progress_interval()->set_nanos(10'000'000);
  request.mutable_intermediate_interval()->set_nanos(10'000'000);
  std::vector<v1::QuantizeEvent> events;
  const client::JobOutcome outcome =
      client.Quantize(request, StreamFor(kJobTimeout, [&events](const v1::QuantizeEvent& event) {
                        events.push_back(event);
                        return true;
                      }));
  ASSERT_TRUE(outcome.status.ok()) << outcome.status << "\n" << server->Log();
  ASSERT_TRUE(outcome.result.has_value());
  EXPECT_TRUE(outcome.job_ended);
  EXPECT_TRUE(IsValidResult(mesh, *outcome.result));
  EXPECT_EQ(outcome.result->mesh_name(), mesh.name());
  EXPECT_EQ(outcome.result->termination(), v1::CONVERGED);

  // accepted, at least one progress, ..., result; one job, increasing numbers from 0.
  ASSERT_GE(events.size(), 3u);
  ASSERT_TRUE(events.front().has_accepted());
  const std::string job = events.front().job();
  EXPECT_THAT(job, StartsWith("jobs/"));
  EXPECT_EQ(outcome.job, job);
  EXPECT_EQ(events.front().sequence(), 0);
  const TMesh core_mesh = TMeshOrDie(mesh);
  EXPECT_TRUE(MessageDifferencer::Equals(events.front().accepted().mesh_stats(),
                                         MeshStatsToProto(ComputeMeshStats(core_mesh))));
  EXPECT_EQ(events.front().accepted().mesh_display_name(), mesh.name());
  const double scaling = events.front().accepted().scaling();
  EXPECT_DOUBLE_EQ(scaling, outcome.result->scaling());
  ASSERT_TRUE(events.back().has_result());
  int progress_events = 0;
  IntermediateSequenceChecker intermediates(mesh, scaling);
  for (size_t i = 0; i < events.size(); ++i) {
    const v1::QuantizeEvent& event = events[i];
    EXPECT_EQ(event.job(), job);
    if (i > 0) {
      EXPECT_GT(event.sequence(), events[i - 1].sequence());
    }
    if (i > 0 && i + 1 < events.size()) {
      EXPECT_TRUE(event.has_progress() || event.has_intermediate()) << event.DebugString();
    }
    if (event.has_progress()) ++progress_events;
    if (event.has_intermediate()) intermediates.Check(event);
  }
  EXPECT_GE(progress_events, 1);

  // The service runs the same code as an in-process solve: the same q.
  v1::QuantizationOptions options;
  options.mutable_scaling()->set_level_percent(GetParam().level);
  const absl::StatusOr<QuantizeOptions> resolved = QuantizeOptionsFromProto(options, core_mesh);
  ASSERT_TRUE(resolved.ok());
  const absl::StatusOr<QuantizeResult> local = Quantize(core_mesh, *resolved);
  ASSERT_TRUE(local.ok());
  EXPECT_THAT(outcome.result->q(), ElementsAreArray(local->q));
  EXPECT_DOUBLE_EQ(outcome.result->objective(), local->objective);
  EXPECT_EQ(outcome.result->hexes(), local->hexes);

  // The job stays retrievable, bound to the call that ran it.
  const absl::StatusOr<v1::Job> after = client.GetJob(job);
  ASSERT_TRUE(after.ok()) << after.status();
  EXPECT_EQ(after->state(), v1::SUCCEEDED);
  EXPECT_TRUE(after->done());
  EXPECT_TRUE(after->bound_to_call());
  EXPECT_EQ(after->event_count(), events.back().sequence() + 1);
  EXPECT_TRUE(MessageDifferencer::Equals(after->result(), *outcome.result));
  EXPECT_TRUE(server->WaitForLog("event=job_end job=" + job + " state=SUCCEEDED")) << server->Log();
}

INSTANTIATE_TEST_SUITE_P(
    RealTMeshes, QuantizeStreamTest,
    ::testing::Values(Instance{"hex-me/s07c_notch.tmesh.json", 100},
                      Instance{"singularity-constrained-fields/fanpart.tmesh.json", 10},
                      Instance{"hex-me/s04u_tetrahedron.tmesh.json", 1},
                      Instance{"2019_-_Selective_Padding_for_Polycube‐Based_"
                               "Hexahedral_Meshing_Wrench",
                               50}),
    [](const ::testing::TestParamInfo<Instance>& info) {
      return "Instance" + std::to_string(info.index);
    });

TEST(IntermediateQuantizationTest, ALongJobSendsImprovingQuantizationsAtTheRequestedRate) {
  std::unique_ptr<ServerProcess> server = StartServerOrFail({"--workers=1"});
  ASSERT_NE(server, nullptr);
  client::QuantizerClient client = ClientOf(*server);
  const v1::TMesh mesh = MeshTakingSeconds(2);
  v1::QuantizeRequest request = RequestFor(mesh, 100);
  request.mutable_intermediate_interval()->set_nanos(200'000'000);
  std::vector<v1::QuantizeEvent> intermediates;
  double scaling = 0;
  const client::JobOutcome outcome =
      client.Quantize(request, StreamFor(kJobTimeout, [&](const v1::QuantizeEvent& event) {
                        if (event.has_accepted()) scaling = event.accepted().scaling();
                        if (event.has_intermediate()) intermediates.push_back(event);
                        return true;
                      }));
  ASSERT_TRUE(outcome.status.ok()) << outcome.status;
  EXPECT_TRUE(IsValidResult(mesh, *outcome.result));
  // The first report carries q (the job is still running when the stream starts, and the
  // latest intermediate quantization is kept until the result replaces it).
  ASSERT_GE(intermediates.size(), 1u);
  IntermediateSequenceChecker checker(mesh, scaling);
  absl::Time previous = absl::InfinitePast();
  for (const v1::QuantizeEvent& event : intermediates) {
    checker.Check(event);
    const absl::Time sent =
        absl::FromUnixSeconds(event.time().seconds()) + absl::Nanoseconds(event.time().nanos());
    EXPECT_GE(sent - previous,
              absl::Milliseconds(190));  // wall-clock stamps of a steady-clock rate
    previous = sent;
  }
}

TEST(StoredMeshTest, OneUploadServesRunsAtSeveralLevels) {
  std::unique_ptr<ServerProcess> server = StartServerOrFail({"--workers=2"});
  ASSERT_NE(server, nullptr);
  client::QuantizerClient client = ClientOf(*server);
  const v1::TMesh& mesh = NotchMesh();
  const absl::StatusOr<v1::Mesh> stored = client.CreateMesh(mesh);
  ASSERT_TRUE(stored.ok()) << stored.status();
  EXPECT_THAT(stored->name(), StartsWith("meshes/"));
  EXPECT_EQ(stored->display_name(), mesh.name());
  EXPECT_EQ(stored->mesh_stats().arcs(), mesh.arcs_size());

  for (int level : {1, 10, 25, 100}) {
    const client::JobOutcome outcome =
        client.Quantize(StoredMeshRequest(stored->name(), level), StreamFor(kJobTimeout));
    ASSERT_TRUE(outcome.status.ok()) << "level " << level << ": " << outcome.status;
    EXPECT_TRUE(IsValidResult(mesh, *outcome.result)) << "level " << level;
    const absl::StatusOr<v1::Job> job = client.GetJob(outcome.job, v1::BASIC);
    ASSERT_TRUE(job.ok());
    EXPECT_EQ(job->stored_mesh(), stored->name());
    EXPECT_EQ(job->result().q_size(), 0) << "the basic view leaves q out";
  }

  const absl::StatusOr<v1::Mesh> got = client.GetMesh(stored->name());
  ASSERT_TRUE(got.ok()) << got.status();
  EXPECT_EQ(got->name(), stored->name());
  ASSERT_TRUE(client.DeleteMesh(stored->name()).ok());
  const client::JobOutcome after_delete =
      client.Quantize(StoredMeshRequest(stored->name(), 100), StreamFor(kJobTimeout));
  EXPECT_EQ(after_delete.status.code(), absl::StatusCode::kNotFound) << after_delete.status;
  EXPECT_THAT(std::string(after_delete.status.message()), ::testing::HasSubstr("upload it again"));
  EXPECT_EQ(client.DeleteMesh(stored->name()).code(), absl::StatusCode::kNotFound);
}

TEST(StoredMeshTest, LeastRecentlyUsedMeshIsEvictedBeyondTheLimit) {
  std::unique_ptr<ServerProcess> server = StartServerOrFail({"--max_stored_meshes=2"});
  ASSERT_NE(server, nullptr);
  client::QuantizerClient client = ClientOf(*server);
  const absl::StatusOr<v1::Mesh> first = client.CreateMesh(NotchMesh());
  const absl::StatusOr<v1::Mesh> second = client.CreateMesh(NotchMesh());
  ASSERT_TRUE(first.ok() && second.ok());
  ASSERT_TRUE(client.GetMesh(first->name()).ok());  // first is now the most recently used
  const absl::StatusOr<v1::Mesh> third = client.CreateMesh(NotchMesh());
  ASSERT_TRUE(third.ok());
  EXPECT_TRUE(client.GetMesh(first->name()).ok());
  EXPECT_EQ(client.GetMesh(second->name()).status().code(), absl::StatusCode::kNotFound);
  EXPECT_TRUE(client.GetMesh(third->name()).ok());
}

}  // namespace
}  // namespace ispq::testing
