// SPDX-License-Identifier: Apache-2.0
// The reactor that streams a job's events to a client (server/grpc/job_event_stream.h), behind the
// service's Quantize and WatchJob on an in-process gRPC server: every event once, in order, from
// the requested one, ending with the job's status; a Quantize call's job is cancelled with the
// call; a job's events reach a watcher that attached before they happened.
#include "server/grpc/job_event_stream.h"

#include <memory>
#include <string>
#include <vector>

#include "core/proto/quantization_proto.h"
#include "core/quantization_validator.h"
#include "grpcpp/grpcpp.h"
#include "gtest/gtest.h"
#include "ispq/v1/service.grpc.pb.h"
#include "server/grpc/quantizer_service.h"
#include "server/store/mesh_store.h"
#include "tests/support/bounded_wait.h"
#include "tests/support/test_data.h"

namespace ispq::server {
namespace {

constexpr char kNotch[] = "hex-me/s07c_notch.tmesh.json";

v1::QuantizeRequest NotchRequest() {
  v1::QuantizeRequest request;
  *request.mutable_mesh() = testing::LoadProtoOrDie(testing::RealTMeshPath(kNotch));
  request.mutable_options()->mutable_scaling()->set_level_percent(25);
  return request;
}

// Reads a stream to its end: its events and final status.
struct ReadStream {
  std::vector<v1::QuantizeEvent> events;
  grpc::Status status;
};
ReadStream ReadAll(grpc::ClientReaderInterface<v1::QuantizeEvent>& reader) {
  ReadStream read;
  v1::QuantizeEvent event;
  while (reader.Read(&event)) read.events.push_back(event);
  read.status = reader.Finish();
  return read;
}

class JobEventStreamTest : public ::testing::TestWithParam<int> {
 protected:
  JobEventStreamTest()
      : budget_(1 << 30),
        meshes_(10),
        scheduler_({.workers = GetParam(), .max_queued_jobs = 8, .retention = {}}, metrics_,
                   &budget_),
        memory_(budget_, scheduler_, meshes_, metrics_),
        authenticator_(AuthenticationConfig{}),
        job_service_({scheduler_, meshes_, metrics_, memory_}, JobLimits{.max_arcs = 1000000},
                     AdmissionConfig{}),
        service_(job_service_, authenticator_) {
    grpc::ServerBuilder builder;
    builder.RegisterService(&service_);
    server_ = builder.BuildAndStart();
    stub_ = v1::Quantizer::NewStub(server_->InProcessChannel(grpc::ChannelArguments()));
  }
  ~JobEventStreamTest() override {
    scheduler_.StopAccepting();
    server_->Shutdown();
  }

  ServerMetrics metrics_;
  MemoryBudget budget_;
  InMemoryMeshStore meshes_;
  JobScheduler scheduler_;
  MemoryAdmission memory_;
  Authenticator authenticator_;
  JobService job_service_;
  QuantizerService service_;  // the gRPC adapter over job_service_
  std::unique_ptr<grpc::Server> server_;
  std::unique_ptr<v1::Quantizer::Stub> stub_;
};

class WithAWorker : public JobEventStreamTest {};

TEST_P(WithAWorker, QuantizeStreamsEveryEventOnceInOrderAndEndsWithTheResult) {
  grpc::ClientContext context;
  auto reader = stub_->Quantize(&context, NotchRequest());
  const ReadStream read = ReadAll(*reader);
  ASSERT_TRUE(read.status.ok()) << read.status.error_message();
  ASSERT_GE(read.events.size(), 2u);
  EXPECT_TRUE(read.events.front().has_accepted());
  for (size_t i = 0; i < read.events.size(); ++i) {
    EXPECT_EQ(read.events[i].job(), read.events.front().job());
    if (i > 0) {
      EXPECT_GT(read.events[i].sequence(), read.events[i - 1].sequence());
    }
  }
  ASSERT_TRUE(read.events.back().has_result());
  const TMesh mesh = testing::LoadTMeshOrDie(testing::RealTMeshPath(kNotch));
  const absl::StatusOr<std::vector<int64_t>> q =
      QuantizationFromProto(read.events.back().result(), mesh);
  ASSERT_TRUE(q.ok()) << q.status();
  const absl::StatusOr<ValidationReport> report = ValidateQuantization(mesh, *q);
  ASSERT_TRUE(report.ok()) << report.status();
  EXPECT_TRUE(report->valid()) << report->Describe();

  // A watcher of the ended job from a later event gets the tail from there: the retained events
  // at or after it (the log keeps only the newest of superseded progress), to the same end.
  grpc::ClientContext watch_context;
  v1::WatchJobRequest watch;
  watch.set_name(read.events.front().job());
  watch.set_from_event(read.events[1].sequence());
  auto watcher = stub_->WatchJob(&watch_context, watch);
  const ReadStream tail = ReadAll(*watcher);
  ASSERT_TRUE(tail.status.ok()) << tail.status.error_message();
  ASSERT_FALSE(tail.events.empty());
  EXPECT_GE(tail.events.front().sequence(), read.events[1].sequence());
  EXPECT_EQ(tail.events.back().sequence(), read.events.back().sequence());
  EXPECT_TRUE(tail.events.back().has_result());
}

class WithoutWorkers : public JobEventStreamTest {};

TEST_P(WithoutWorkers, AQuantizeCallsJobIsCancelledWithTheCall) {
  auto context = std::make_unique<grpc::ClientContext>();
  auto reader = stub_->Quantize(context.get(), NotchRequest());
  v1::QuantizeEvent accepted;
  ASSERT_TRUE(reader->Read(&accepted));
  ASSERT_TRUE(accepted.has_accepted());
  const std::shared_ptr<Job> job = scheduler_.Find(std::string(accepted.job()).substr(5));
  ASSERT_NE(job, nullptr);
  EXPECT_EQ(job->state(), v1::QUEUED);
  context->TryCancel();
  ReadAll(*reader);
  ASSERT_TRUE(testing::WaitUntil([&] { return job->done(); }));
  EXPECT_EQ(job->state(), v1::CANCELLED);
}

TEST_P(WithoutWorkers, AWatcherHearsOfTheEndOfAJobItAttachedToBefore) {
  grpc::ClientContext submit_context;
  v1::Job submitted;
  ASSERT_TRUE(stub_->SubmitJob(&submit_context, NotchRequest(), &submitted).ok());

  grpc::ClientContext watch_context;
  v1::WatchJobRequest watch;
  watch.set_name(submitted.name());
  auto watcher = stub_->WatchJob(&watch_context, watch);
  v1::QuantizeEvent first;
  ASSERT_TRUE(watcher->Read(&first));
  EXPECT_TRUE(first.has_accepted());

  grpc::ClientContext cancel_context;
  v1::CancelJobRequest cancel;
  cancel.set_name(submitted.name());
  v1::Job cancelled;
  ASSERT_TRUE(stub_->CancelJob(&cancel_context, cancel, &cancelled).ok());
  const ReadStream rest = ReadAll(*watcher);
  ASSERT_FALSE(rest.events.empty());
  EXPECT_TRUE(rest.events.back().has_error());
  EXPECT_EQ(rest.status.error_code(), grpc::StatusCode::CANCELLED);
}

INSTANTIATE_TEST_SUITE_P(OneWorker, WithAWorker, ::testing::Values(1));
INSTANTIATE_TEST_SUITE_P(NoWorker, WithoutWorkers, ::testing::Values(0));

}  // namespace
}  // namespace ispq::server
