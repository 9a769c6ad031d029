// SPDX-License-Identifier: Apache-2.0
// QuantizerClient against a scripted Quantizer service on an in-process gRPC server: streamed
// events reach the handler in order and the outcome says how the job ended (result, error event)
// or where its stream broke; a handler that stops cancels the call on the server; FollowJob
// resumes after transient breaks from the next event and gives up on other errors; unary errors
// keep their code and message; and the bearer token is sent on every call.
#include "client/quantizer_client.h"

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "absl/base/thread_annotations.h"
#include "absl/synchronization/mutex.h"
#include "gmock/gmock.h"
#include "grpcpp/server.h"
#include "grpcpp/server_builder.h"
#include "grpcpp/server_context.h"
#include "gtest/gtest.h"
#include "tests/support/bounded_wait.h"

namespace ispq::client {
namespace {

using ::testing::ElementsAre;

// One scripted stream: these events, then this status.
struct Stream {
  std::vector<v1::QuantizeEvent> events;
  grpc::Status status = grpc::Status::OK;
  bool wait_for_cancel = false;  // after the events, until the client cancels
};

v1::QuantizeEvent Event(int64_t sequence) {
  v1::QuantizeEvent event;
  event.set_job("jobs/j1");
  event.set_sequence(sequence);
  event.mutable_progress()->set_iteration(sequence);
  return event;
}

v1::QuantizeEvent ResultEvent(int64_t sequence) {
  v1::QuantizeEvent event = Event(sequence);
  event.mutable_result()->set_valid(true);
  event.mutable_result()->add_q(4);
  return event;
}

class ScriptedQuantizer final : public v1::Quantizer::Service {
 public:
  void Script(std::vector<Stream> streams) {
    absl::MutexLock lock(&mu_);
    streams_ = std::move(streams);
  }
  std::vector<int64_t> watched_from() const {
    absl::MutexLock lock(&mu_);
    return watched_from_;
  }
  std::vector<std::string> authorizations() const {
    absl::MutexLock lock(&mu_);
    return authorizations_;
  }
  bool saw_cancel() const {
    absl::MutexLock lock(&mu_);
    return saw_cancel_;
  }

  grpc::Status Quantize(grpc::ServerContext* context, const v1::QuantizeRequest*,
                        grpc::ServerWriter<v1::QuantizeEvent>* writer) override {
    return Play(context, writer);
  }
  grpc::Status WatchJob(grpc::ServerContext* context, const v1::WatchJobRequest* request,
                        grpc::ServerWriter<v1::QuantizeEvent>* writer) override {
    {
      absl::MutexLock lock(&mu_);
      watched_from_.push_back(request->from_event());
    }
    return Play(context, writer);
  }
  grpc::Status GetJob(grpc::ServerContext* context, const v1::GetJobRequest* request,
                      v1::Job* job) override {
    Record(context);
    job->set_name(request->name());
    return grpc::Status::OK;
  }
  grpc::Status SubmitJob(grpc::ServerContext* context, const v1::QuantizeRequest*,
                         v1::Job*) override {
    Record(context);
    return grpc::Status(grpc::StatusCode::FAILED_PRECONDITION, "the queue is closed");
  }

 private:
  void Record(grpc::ServerContext* context) {
    const auto& metadata = context->client_metadata();
    const auto it = metadata.find("authorization");
    absl::MutexLock lock(&mu_);
    authorizations_.push_back(
        it == metadata.end() ? "" : std::string(it->second.data(), it->second.size()));
  }

  grpc::Status Play(grpc::ServerContext* context, grpc::ServerWriter<v1::QuantizeEvent>* writer) {
    Record(context);
    Stream stream;
    {
      absl::MutexLock lock(&mu_);
      if (streams_.empty()) return grpc::Status(grpc::StatusCode::INTERNAL, "no script left");
      stream = streams_.front();
      if (streams_.size() > 1) streams_.erase(streams_.begin());
    }
    for (const v1::QuantizeEvent& event : stream.events) writer->Write(event);
    if (stream.wait_for_cancel) {
      if (testing::WaitUntil([context] { return context->IsCancelled(); })) {
        absl::MutexLock lock(&mu_);
        saw_cancel_ = true;
      }
      return grpc::Status::CANCELLED;
    }
    return stream.status;
  }

  mutable absl::Mutex mu_;
  std::vector<Stream> streams_ ABSL_GUARDED_BY(mu_);
  std::vector<int64_t> watched_from_ ABSL_GUARDED_BY(mu_);
  std::vector<std::string> authorizations_ ABSL_GUARDED_BY(mu_);
  bool saw_cancel_ ABSL_GUARDED_BY(mu_) = false;
};

class QuantizerClientTest : public ::testing::Test {
 protected:
  QuantizerClientTest() {
    grpc::ServerBuilder builder;
    builder.RegisterService(&service_);
    server_ = builder.BuildAndStart();
    client_ = std::make_unique<QuantizerClient>(server_->InProcessChannel(grpc::ChannelArguments()),
                                                "secret", absl::Seconds(30));
  }
  ~QuantizerClientTest() override { server_->Shutdown(); }

  // Runs `call` with a handler that records the sequence numbers it sees.
  template <typename Call>
  JobOutcome Collect(Call call, std::vector<int64_t>& seen) {
    StreamOptions options;
    options.on_event = [&seen](const v1::QuantizeEvent& event) {
      seen.push_back(event.sequence());
      return true;
    };
    options.timeout = testing::kSafetyNet;
    return call(options);
  }

  ScriptedQuantizer service_;
  std::unique_ptr<grpc::Server> server_;
  std::unique_ptr<QuantizerClient> client_;
};

TEST_F(QuantizerClientTest, QuantizeHandsOverEveryEventAndReturnsTheResult) {
  service_.Script({{.events = {Event(0), Event(1), ResultEvent(2)}}});
  std::vector<int64_t> seen;
  const JobOutcome outcome = Collect(
      [this](const StreamOptions& o) { return client_->Quantize(v1::QuantizeRequest(), o); }, seen);
  EXPECT_THAT(seen, ElementsAre(0, 1, 2));
  EXPECT_EQ(outcome.job, "jobs/j1");
  ASSERT_TRUE(outcome.result.has_value());
  EXPECT_THAT(outcome.result->q(), ElementsAre(4));
  EXPECT_TRUE(outcome.status.ok()) << outcome.status;
  EXPECT_TRUE(outcome.job_ended);
  EXPECT_EQ(outcome.next_event, 3);
  EXPECT_THAT(service_.authorizations(), ElementsAre("Bearer secret"));
}

// The job's error event is its outcome, whatever status the stream then ends with.
TEST_F(QuantizerClientTest, AnErrorEventEndsTheJobWithItsStatus) {
  v1::QuantizeEvent error = Event(1);
  error.mutable_error()->set_code(static_cast<int>(absl::StatusCode::kInvalidArgument));
  error.mutable_error()->set_message("arc 3: length 0");
  service_.Script({{.events = {Event(0), error}, .status = grpc::Status::OK}});
  const JobOutcome outcome = client_->Quantize(v1::QuantizeRequest(), {});
  EXPECT_TRUE(outcome.job_ended);
  EXPECT_FALSE(outcome.result.has_value());
  EXPECT_EQ(outcome.status, absl::InvalidArgumentError("arc 3: length 0"));
}

TEST_F(QuantizerClientTest, ABrokenStreamSaysWhereToResume) {
  service_.Script({{.events = {Event(0), Event(1)},
                    .status = grpc::Status(grpc::StatusCode::UNAVAILABLE, "proxy restarting")}});
  const JobOutcome outcome = client_->WatchJob("jobs/j1", 0, {});
  EXPECT_FALSE(outcome.job_ended);
  EXPECT_EQ(outcome.status, absl::UnavailableError("proxy restarting"));
  EXPECT_EQ(outcome.job, "jobs/j1");
  EXPECT_EQ(outcome.next_event, 2);
}

// A stream the server ends successfully without a terminal event: the job ended before the
// first event asked for.
TEST_F(QuantizerClientTest, WatchingPastTheEndIsOutOfRange) {
  service_.Script({{.events = {}, .status = grpc::Status::OK}});
  const JobOutcome outcome = client_->WatchJob("jobs/j1", 5, {});
  EXPECT_EQ(outcome.status.code(), absl::StatusCode::kOutOfRange);
  EXPECT_EQ(outcome.next_event, 5);
  EXPECT_THAT(service_.watched_from(), ElementsAre(5));
}

TEST_F(QuantizerClientTest, AHandlerThatStopsCancelsTheCall) {
  service_.Script({{.events = {Event(0), Event(1)}, .wait_for_cancel = true}});
  StreamOptions options;
  int calls = 0;
  options.on_event = [&calls](const v1::QuantizeEvent&) {
    ++calls;
    return false;
  };
  const JobOutcome outcome = client_->Quantize(v1::QuantizeRequest(), options);
  EXPECT_EQ(calls, 1);
  EXPECT_EQ(outcome.status, absl::CancelledError("the event handler stopped the stream"));
  EXPECT_FALSE(outcome.job_ended);
  EXPECT_EQ(outcome.next_event, 1);
  EXPECT_TRUE(testing::WaitUntil([this] { return service_.saw_cancel(); }));
}

TEST_F(QuantizerClientTest, FollowJobResumesFromTheNextEventAfterATransientBreak) {
  service_.Script({{.events = {Event(0), Event(1)},
                    .status = grpc::Status(grpc::StatusCode::UNAVAILABLE, "connection reset")},
                   {.events = {Event(2), ResultEvent(3)}}});
  std::vector<int64_t> seen;
  const JobOutcome outcome =
      Collect([this](const StreamOptions& o) { return client_->FollowJob("jobs/j1", 0, o); }, seen);
  ASSERT_TRUE(outcome.result.has_value()) << outcome.status;
  EXPECT_THAT(seen, ElementsAre(0, 1, 2, 3));
  EXPECT_THAT(service_.watched_from(), ElementsAre(0, 2));
  EXPECT_THAT(service_.authorizations(), ElementsAre("Bearer secret", "Bearer secret"));
}

TEST_F(QuantizerClientTest, FollowJobGivesUpOnOtherErrorsAndAfterItsAttempts) {
  service_.Script(
      {{.events = {}, .status = grpc::Status(grpc::StatusCode::NOT_FOUND, "no such job")}});
  JobOutcome outcome = client_->FollowJob("jobs/gone", 0, {});
  EXPECT_EQ(outcome.status, absl::NotFoundError("no such job"));
  EXPECT_THAT(service_.watched_from(), ElementsAre(0));

  service_.Script({{.events = {Event(0)},
                    .status = grpc::Status(grpc::StatusCode::UNAVAILABLE, "still down")}});
  outcome = client_->FollowJob("jobs/j1", 0, {}, /*max_attempts=*/2);
  EXPECT_EQ(outcome.status.code(), absl::StatusCode::kUnavailable);
  EXPECT_EQ(outcome.next_event, 1);
  EXPECT_THAT(service_.watched_from(), ElementsAre(0, 0, 1));
}

TEST_F(QuantizerClientTest, UnaryCallsKeepTheServersCodeAndMessage) {
  const absl::StatusOr<v1::Job> submitted = client_->SubmitJob(v1::QuantizeRequest());
  EXPECT_EQ(submitted.status(), absl::FailedPreconditionError("the queue is closed"));
  const absl::StatusOr<v1::Job> job = client_->GetJob("jobs/abc");
  ASSERT_TRUE(job.ok()) << job.status();
  EXPECT_EQ(job->name(), "jobs/abc");
  EXPECT_THAT(service_.authorizations(), ElementsAre("Bearer secret", "Bearer secret"));
}

TEST_F(QuantizerClientTest, WithoutATokenNoAuthorizationIsSent) {
  QuantizerClient anonymous(server_->InProcessChannel(grpc::ChannelArguments()));
  ASSERT_TRUE(anonymous.GetJob("jobs/abc").ok());
  EXPECT_THAT(service_.authorizations(), ElementsAre(""));
}

TEST(QuantizerClientNamesTest, JobNamesAcceptTheBareId) {
  EXPECT_EQ(JobName("abc"), "jobs/abc");
  EXPECT_EQ(JobName("jobs/abc"), "jobs/abc");
}

TEST(QuantizerClientNamesTest, GrpcStatusesKeepCodeAndMessage) {
  EXPECT_TRUE(StatusFromGrpc(grpc::Status::OK).ok());
  EXPECT_EQ(StatusFromGrpc(grpc::Status(grpc::StatusCode::RESOURCE_EXHAUSTED, "queue full")),
            absl::ResourceExhaustedError("queue full"));
}

}  // namespace
}  // namespace ispq::client
