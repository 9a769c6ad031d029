// SPDX-License-Identifier: Apache-2.0
// UnaryCall (server/grpc/unary_call.h), the reactor of every unary method, behind a GetJob method
// of a test service on an in-process gRPC server: an answer reaches the client from whichever
// thread gives it, accounted in the memory budget at its size and let go once the call is done;
// an answer the budget cannot hold becomes RESOURCE_EXHAUSTED; a failure carries its status and,
// with a retry hint, the grpc-retry-pushback-ms trailer.
#include "server/grpc/unary_call.h"

#include <functional>
#include <memory>
#include <string>

#include "absl/base/thread_annotations.h"
#include "absl/synchronization/mutex.h"
#include "absl/synchronization/notification.h"
#include "gmock/gmock.h"
#include "grpcpp/grpcpp.h"
#include "gtest/gtest.h"
#include "ispq/v1/service.grpc.pb.h"
#include "server/jobs/retry_hint.h"
#include "server/store/mesh_store.h"
#include "tests/support/bounded_wait.h"

namespace ispq::server {
namespace {

using ::testing::HasSubstr;

// GetJob answered through a UnaryCall by what the test puts in `handle`.
class UnaryCallService
    : public v1::Quantizer::WithRawCallbackMethod_GetJob<v1::Quantizer::Service> {
 public:
  explicit UnaryCallService(MemoryAdmission* memory) : memory_(memory) {}

  void SetHandler(std::function<void(UnaryCall*)> handle) {
    absl::MutexLock lock(&mutex_);
    handle_ = std::move(handle);
  }

  grpc::ServerUnaryReactor* GetJob(grpc::CallbackServerContext* context, const grpc::ByteBuffer*,
                                   grpc::ByteBuffer* response) override {
    auto* call = new UnaryCall(context, response, memory_);
    std::function<void(UnaryCall*)> handle;
    {
      absl::MutexLock lock(&mutex_);
      handle = handle_;
    }
    handle(call);
    return call;
  }

 private:
  MemoryAdmission* const memory_;
  absl::Mutex mutex_;
  std::function<void(UnaryCall*)> handle_ ABSL_GUARDED_BY(mutex_);
};

// A job with a result of `arcs` lengths: a response of some size.
v1::Job JobWithResult(int arcs) {
  v1::Job job;
  job.set_name("jobs/0123456789abcdef");
  for (int i = 0; i < arcs; ++i) job.mutable_result()->add_q(i);
  return job;
}

class UnaryCallTest : public ::testing::Test {
 protected:
  static constexpr int64_t kLimit = 16 << 20;

  UnaryCallTest()
      : budget_(kLimit),
        meshes_(10),
        scheduler_({.workers = 0, .max_queued_jobs = 1, .retention = {}}, metrics_, &budget_),
        memory_(budget_, scheduler_, meshes_, metrics_),
        service_(&memory_) {
    grpc::ServerBuilder builder;
    builder.RegisterService(&service_);
    server_ = builder.BuildAndStart();
    stub_ = v1::Quantizer::NewStub(server_->InProcessChannel(grpc::ChannelArguments()));
  }
  ~UnaryCallTest() override {
    scheduler_.StopAccepting();
    server_->Shutdown();
  }

  // Calls GetJob and returns its status, the response in `job`.
  grpc::Status Call(v1::Job* job, grpc::ClientContext* context = nullptr) {
    grpc::ClientContext own;
    return stub_->GetJob(context != nullptr ? context : &own, v1::GetJobRequest(), job);
  }

  static std::string RetryTrailer(const grpc::ClientContext& context) {
    const auto& trailers = context.GetServerTrailingMetadata();
    const auto it = trailers.find("grpc-retry-pushback-ms");
    return it == trailers.end() ? "" : std::string(it->second.data(), it->second.size());
  }

  ServerMetrics metrics_;
  MemoryBudget budget_;
  InMemoryMeshStore meshes_;
  JobScheduler scheduler_;
  MemoryAdmission memory_;
  UnaryCallService service_;
  std::unique_ptr<grpc::Server> server_;
  std::unique_ptr<v1::Quantizer::Stub> stub_;
};

TEST_F(UnaryCallTest, AnAnswerReachesTheClientAccountedAtItsSizeAndIsThenLetGo) {
  const v1::Job answer = JobWithResult(100000);
  service_.SetHandler([&](UnaryCall* call) { call->Answer(answer); });
  v1::Job received;
  const grpc::Status status = Call(&received);
  ASSERT_TRUE(status.ok()) << status.error_message();
  EXPECT_EQ(received.SerializeAsString(), answer.SerializeAsString());
  // The response was the only thing accounted, at its serialized size, and is let go once sent.
  EXPECT_EQ(budget_.ToProto().peak_used_bytes(), static_cast<int64_t>(answer.ByteSizeLong()));
  EXPECT_TRUE(testing::WaitUntil([&] { return budget_.used(MemoryUse::kResponses) == 0; }));
}

// Admission threads answer calls that gRPC's thread handed over and left.
TEST_F(UnaryCallTest, AnAnswerMayComeFromAnotherThreadLater) {
  absl::Mutex mutex;
  UnaryCall* pending = nullptr;
  service_.SetHandler([&](UnaryCall* call) {
    absl::MutexLock lock(&mutex);
    pending = call;
  });
  grpc::ClientContext context;
  v1::GetJobRequest request;
  v1::Job received;
  absl::Notification done;
  grpc::Status status;
  stub_->async()->GetJob(&context, &request, &received, [&](grpc::Status s) {
    status = std::move(s);
    done.Notify();
  });
  ASSERT_TRUE(testing::WaitUntil([&] {
    absl::MutexLock lock(&mutex);
    return pending != nullptr;
  }));
  EXPECT_FALSE(done.HasBeenNotified());
  {
    absl::MutexLock lock(&mutex);
    pending->Answer(JobWithResult(3));
  }
  ASSERT_TRUE(done.WaitForNotificationWithTimeout(testing::kSafetyNet));
  ASSERT_TRUE(status.ok()) << status.error_message();
  EXPECT_EQ(received.result().q_size(), 3);
}

// The budget is held by running jobs; the response would overdraw it. The client hears why and
// when to come back (the jobs will end), and nothing of the response stays accounted.
TEST_F(UnaryCallTest, AnAnswerTheBudgetCannotHoldIsResourceExhausted) {
  MemoryReservation running = budget_.ForceReserve(MemoryUse::kJobs, kLimit - 1000);
  service_.SetHandler([](UnaryCall* call) { call->Answer(JobWithResult(100000)); });
  grpc::ClientContext context;
  v1::Job received;
  const grpc::Status status = Call(&received, &context);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
  EXPECT_THAT(status.error_message(), HasSubstr("the response"));
  EXPECT_FALSE(RetryTrailer(context).empty());
  EXPECT_EQ(budget_.used(MemoryUse::kResponses), 0);
}

TEST_F(UnaryCallTest, AFailureCarriesItsStatusAndItsRetryHintAsTheTrailer) {
  service_.SetHandler([](UnaryCall* call) {
    call->Fail(ResourceExhaustedWithRetryHint("the queue is full", absl::Milliseconds(1500)));
  });
  grpc::ClientContext busy_context;
  v1::Job received;
  const grpc::Status busy = Call(&received, &busy_context);
  EXPECT_EQ(busy.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
  EXPECT_THAT(busy.error_message(), HasSubstr("the queue is full"));
  EXPECT_EQ(RetryTrailer(busy_context), "1500");

  service_.SetHandler([](UnaryCall* call) { call->Fail(absl::NotFoundError("no such job")); });
  grpc::ClientContext missing_context;
  const grpc::Status missing = Call(&received, &missing_context);
  EXPECT_EQ(missing.error_code(), grpc::StatusCode::NOT_FOUND);
  EXPECT_EQ(missing.error_message(), "no such job");
  EXPECT_EQ(RetryTrailer(missing_context), "");
}

}  // namespace
}  // namespace ispq::server
