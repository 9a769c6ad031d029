// SPDX-License-Identifier: Apache-2.0
// The server's limits: a bounded queue that answers RESOURCE_EXHAUSTED with a retry hint,
// client deadlines that cancel queued and running jobs, the server's own job time limit, and
// the size limits on meshes and messages. After each refusal the server keeps serving.
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "absl/strings/numbers.h"
#include "client/health_check.h"
#include "gmock/gmock.h"
#include "grpcpp/client_context.h"
#include "gtest/gtest.h"
#include "ispq/v1/service.grpc.pb.h"
#include "tests/integration/service_test_support.h"
#include "tests/support/bounded_wait.h"
#include "tests/support/tmesh_copies.h"

namespace ispq::testing {
namespace {

using ::testing::HasSubstr;

void ExpectStillServing(ServerProcess& server) {
  EXPECT_TRUE(server.running());
  client::QuantizerClient client = ClientOf(server);
  const absl::StatusOr<client::ServingStatus> health =
      client::CheckHealth(client.channel(), "", kSafetyNet);
  ASSERT_TRUE(health.ok()) << health.status();
  EXPECT_EQ(*health, client::ServingStatus::kServing);
}

TEST(AdmissionTest, FullQueueIsResourceExhaustedWithARetryHint) {
  std::unique_ptr<ServerProcess> server = StartServerOrFail({"--workers=1", "--max_queued_jobs=2"});
  ASSERT_NE(server, nullptr);
  client::QuantizerClient client = ClientOf(*server);
  const absl::StatusOr<v1::Mesh> stored = client.CreateMesh(LongRunningMesh());
  ASSERT_TRUE(stored.ok()) << stored.status();
  const v1::QuantizeRequest request = StoredMeshRequest(stored->name(), 100);

  std::vector<std::string> accepted;
  const absl::StatusOr<v1::Job> running = client.SubmitJob(request);
  ASSERT_TRUE(running.ok()) << running.status();
  accepted.push_back(running->name());
  ASSERT_TRUE(WaitForState(client, running->name(), v1::RUNNING).ok());
  for (int i = 0; i < 2; ++i) {
    const absl::StatusOr<v1::Job> queued = client.SubmitJob(request);
    ASSERT_TRUE(queued.ok()) << queued.status();
    accepted.push_back(queued->name());
  }

  const absl::StatusOr<v1::Job> refused = client.SubmitJob(request);
  EXPECT_EQ(refused.status().code(), absl::StatusCode::kResourceExhausted);
  EXPECT_THAT(std::string(refused.status().message()), HasSubstr("queue is full"));
  EXPECT_THAT(std::string(refused.status().message()), HasSubstr("retry in"));
  const client::JobOutcome streamed = client.Quantize(request, StreamFor(kJobTimeout));
  EXPECT_EQ(streamed.status.code(), absl::StatusCode::kResourceExhausted) << streamed.status;
  EXPECT_TRUE(streamed.job.empty()) << "no job was created";

  // The hint is also in the standard trailer (gRFC A6) for clients with a retry policy.
  std::unique_ptr<v1::Quantizer::Stub> stub = v1::Quantizer::NewStub(client.channel());
  grpc::ClientContext context;
  v1::Job job;
  const grpc::Status status = stub->SubmitJob(&context, request, &job);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
  const auto& trailers = context.GetServerTrailingMetadata();
  const auto pushback = trailers.find("grpc-retry-pushback-ms");
  ASSERT_NE(pushback, trailers.end());
  int64_t milliseconds = 0;
  EXPECT_TRUE(absl::SimpleAtoi(std::string(pushback->second.data(), pushback->second.size()),
                               &milliseconds));
  EXPECT_GE(milliseconds, 100);

  const absl::StatusOr<v1::ServerStats> stats = client.GetServerStats();
  ASSERT_TRUE(stats.ok());
  EXPECT_EQ(stats->queued_jobs(), 2);
  EXPECT_EQ(stats->busy_workers(), 1);
  EXPECT_EQ(stats->rejected_queue_full_total(), 3);
  EXPECT_EQ(stats->retained_jobs().running(), 1);
  EXPECT_EQ(stats->retained_jobs().queued(), 2);

  // Room again after a cancellation.
  ASSERT_TRUE(client.CancelJob(accepted.back()).ok());
  const absl::StatusOr<v1::Job> admitted = client.SubmitJob(request);
  ASSERT_TRUE(admitted.ok()) << admitted.status();
  accepted.push_back(admitted->name());
  for (const std::string& name : accepted) ASSERT_TRUE(client.CancelJob(name).ok());
  ExpectStillServing(*server);
}

// The client deadlines of these tests must pass while the job is queued (or running) behind a
// job of about a minute, and after the job was accepted (and started): 10 s leaves room both
// ways on a loaded machine, where 1 s (or 3 s) left little room for the acceptance.
constexpr absl::Duration kClientDeadline = absl::Seconds(10);

TEST(AdmissionTest, DeadlineWhileQueuedCancelsTheJob) {
  std::unique_ptr<ServerProcess> server = StartServerOrFail({"--workers=1"});
  ASSERT_NE(server, nullptr);
  client::QuantizerClient client = ClientOf(*server);
  const absl::StatusOr<v1::Job> running = client.SubmitJob(RequestFor(LongRunningMesh(), 100));
  ASSERT_TRUE(running.ok()) << running.status();

  const client::JobOutcome outcome =
      client.Quantize(RequestFor(NotchMesh(), 100), StreamFor(kClientDeadline));
  EXPECT_EQ(outcome.status.code(), absl::StatusCode::kDeadlineExceeded) << outcome.status;
  ASSERT_FALSE(outcome.job.empty()) << "the accepted event arrived before the deadline";
  const absl::StatusOr<v1::Job> done = WaitUntilDone(client, outcome.job);
  ASSERT_TRUE(done.ok()) << done.status();
  EXPECT_EQ(done->state(), v1::CANCELLED);
  EXPECT_FALSE(done->has_start_time()) << "it never ran";
  EXPECT_THAT(done->error().message(), HasSubstr("cancelled while queued"));
  ASSERT_TRUE(client.CancelJob(running->name()).ok());
}

TEST(AdmissionTest, DeadlineWhileRunningInterruptsTheJob) {
  std::unique_ptr<ServerProcess> server = StartServerOrFail({"--workers=1"});
  ASSERT_NE(server, nullptr);
  client::QuantizerClient client = ClientOf(*server);
  const v1::TMesh& mesh = LongRunningMesh();
  const client::JobOutcome outcome =
      client.Quantize(RequestFor(mesh, 100), StreamFor(kClientDeadline));
  EXPECT_EQ(outcome.status.code(), absl::StatusCode::kDeadlineExceeded) << outcome.status;
  ASSERT_FALSE(outcome.job.empty());
  const absl::StatusOr<v1::Job> done = WaitUntilDone(client, outcome.job);
  ASSERT_TRUE(done.ok()) << done.status();
  EXPECT_EQ(done->state(), v1::CANCELLED);
  EXPECT_TRUE(done->has_start_time());
  ASSERT_TRUE(done->has_result());
  EXPECT_EQ(done->result().termination(), v1::INTERRUPTED);
  if (done->result().valid()) {
    EXPECT_TRUE(IsValidResult(mesh, done->result()));
  }
  ExpectStillServing(*server);
}

TEST(AdmissionTest, ServerTimeLimitStopsLongJobsWithTheirBestResult) {
  std::unique_ptr<ServerProcess> server = StartServerOrFail({"--max_job_seconds=1"});
  ASSERT_NE(server, nullptr);
  client::QuantizerClient client = ClientOf(*server);
  const v1::TMesh& mesh = LongRunningMesh();
  const client::JobOutcome outcome = client.Quantize(RequestFor(mesh, 100), StreamFor(kJobTimeout));
  ASSERT_TRUE(outcome.status.ok()) << outcome.status;
  ASSERT_TRUE(outcome.result.has_value());
  // The limit, not the end of the solve (about a minute), stopped it. How far past the limit
  // the solve went depends on the machine's load: reported only.
  EXPECT_EQ(outcome.result->termination(), v1::TIME_LIMIT);
  std::cout << "stopped after " << outcome.result->stats().solve_seconds()
            << " s of solving (limit 1 s)\n";
  if (outcome.result->valid()) {
    EXPECT_TRUE(IsValidResult(mesh, *outcome.result));
  }
  const absl::StatusOr<v1::Job> job = client.GetJob(outcome.job, v1::BASIC);
  ASSERT_TRUE(job.ok());
  EXPECT_EQ(job->state(), v1::SUCCEEDED);
}

TEST(AdmissionTest, MeshesAboveTheArcLimitAreRefused) {
  std::unique_ptr<ServerProcess> server = StartServerOrFail({"--max_arcs=50"});
  ASSERT_NE(server, nullptr);
  client::QuantizerClient client = ClientOf(*server);
  const client::JobOutcome outcome =
      client.Quantize(RequestFor(NotchMesh(), 100), StreamFor(kJobTimeout));
  EXPECT_EQ(outcome.status.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(outcome.status.message()),
              HasSubstr("mesh has 75 arcs; this server accepts at most 50"));
  EXPECT_EQ(client.CreateMesh(NotchMesh()).status().code(), absl::StatusCode::kInvalidArgument);
  ExpectStillServing(*server);
}

TEST(AdmissionTest, OversizedMessagesAreRefusedByTheTransport) {
  std::unique_ptr<ServerProcess> server = StartServerOrFail({"--max_message_bytes=65536"});
  ASSERT_NE(server, nullptr);
  client::QuantizerClient client = ClientOf(*server);
  const v1::TMesh big = DisjointCopies(NotchMesh(), 20);
  ASSERT_GT(big.ByteSizeLong(), 65536u);
  const absl::StatusOr<v1::Job> refused = client.SubmitJob(RequestFor(big, 100));
  EXPECT_EQ(refused.status().code(), absl::StatusCode::kResourceExhausted) << refused.status();
  EXPECT_THAT(std::string(refused.status().message()), HasSubstr("larger than max"));

  ExpectStillServing(*server);
  const client::JobOutcome small =
      client.Quantize(RequestFor(NotchMesh(), 100), StreamFor(kJobTimeout));
  ASSERT_TRUE(small.status.ok()) << small.status;
  EXPECT_TRUE(IsValidResult(NotchMesh(), *small.result));
}

}  // namespace
}  // namespace ispq::testing
