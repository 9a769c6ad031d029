// SPDX-License-Identifier: Apache-2.0
// The gRPC adapter over the job service (server/grpc/quantizer_service.h), on an in-process gRPC
// server with bearer tokens: every method authenticates its caller before it looks at the
// request, bytes that are no request are INVALID_ARGUMENT naming the expected type, lookups are
// small, the service's errors reach the client with their codes (and a retry hint as the
// grpc-retry-pushback-ms trailer, on unary and streaming calls alike), each method reaches its
// own operation as the token's principal, and the memory the calls took is given back. What
// the operations themselves decide is tested in tests/server/service/job_service_test.cc, the
// event streams in job_event_stream_test.cc.
#include "server/grpc/quantizer_service.h"

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "absl/synchronization/notification.h"
#include "gmock/gmock.h"
#include "grpcpp/generic/generic_stub.h"
#include "grpcpp/grpcpp.h"
#include "gtest/gtest.h"
#include "ispq/v1/service.grpc.pb.h"
#include "server/store/mesh_store.h"
#include "tests/support/bounded_wait.h"
#include "tests/support/test_data.h"

namespace ispq::server {
namespace {

using ::testing::HasSubstr;

constexpr char kAliceToken[] = "token-of-alice";

v1::QuantizeRequest NotchRequest() {
  v1::QuantizeRequest request;
  *request.mutable_mesh() =
      testing::LoadProtoOrDie(testing::RealTMeshPath("hex-me/s07c_notch.tmesh.json"));
  request.mutable_options()->mutable_scaling()->set_level_percent(25);
  return request;
}

// A client context that presents `token` (none if empty).
std::unique_ptr<grpc::ClientContext> As(const std::string& token) {
  auto context = std::make_unique<grpc::ClientContext>();
  if (!token.empty()) context->AddMetadata("authorization", "Bearer " + token);
  return context;
}

// The value of the retry trailer of a finished call, empty if it has none.
std::string RetryTrailer(const grpc::ClientContext& context) {
  const auto& trailers = context.GetServerTrailingMetadata();
  const auto it = trailers.find("grpc-retry-pushback-ms");
  return it == trailers.end() ? "" : std::string(it->second.data(), it->second.size());
}

// A stream read to its end.
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

AuthenticationConfig AliceOnly() {
  AuthenticationConfig config;
  config.tokens = {{"alice", kAliceToken}};
  return config;
}

class QuantizerServiceTest : public ::testing::Test {
 protected:
  QuantizerServiceTest()
      : budget_(1 << 30),
        meshes_(10),
        scheduler_({.workers = 0, .max_queued_jobs = 2, .retention = {}}, metrics_, &budget_),
        memory_(budget_, scheduler_, meshes_, metrics_),
        authenticator_(AliceOnly()),
        job_service_({scheduler_, meshes_, metrics_, memory_}, JobLimits{.max_arcs = 1000000},
                     AdmissionConfig{}),
        service_(job_service_, authenticator_) {
    grpc::ServerBuilder builder;
    builder.RegisterService(&service_);
    server_ = builder.BuildAndStart();
    channel_ = server_->InProcessChannel(grpc::ChannelArguments());
    stub_ = v1::Quantizer::NewStub(channel_);
  }
  ~QuantizerServiceTest() override {
    scheduler_.StopAccepting();
    server_->Shutdown();
  }

  // Calls `method` with `request` as its bytes, as `token`'s principal.
  grpc::Status RawCall(const std::string& method, const std::string& request,
                       const std::string& token = kAliceToken) {
    grpc::GenericStub stub(channel_);
    std::unique_ptr<grpc::ClientContext> context = As(token);
    grpc::Slice slice(request);
    grpc::ByteBuffer request_buffer(&slice, 1);
    grpc::ByteBuffer response;
    grpc::Status status;
    absl::Notification done;
    stub.UnaryCall(context.get(), "/ispq.v1.Quantizer/" + method, grpc::StubOptions(),
                   &request_buffer, &response, [&](grpc::Status s) {
                     status = std::move(s);
                     done.Notify();
                   });
    done.WaitForNotification();
    return status;
  }

  ServerMetrics metrics_;
  MemoryBudget budget_;
  InMemoryMeshStore meshes_;
  JobScheduler scheduler_;
  MemoryAdmission memory_;
  Authenticator authenticator_;
  JobService job_service_;
  QuantizerService service_;
  std::unique_ptr<grpc::Server> server_;
  std::shared_ptr<grpc::Channel> channel_;
  std::unique_ptr<v1::Quantizer::Stub> stub_;
};

TEST_F(QuantizerServiceTest, EveryMethodRefusesACallerWithoutAValidToken) {
  for (const std::string token : {"", "token-of-mallory"}) {
    SCOPED_TRACE("token '" + token + "'");
    const auto code = [&](auto call) {
      std::unique_ptr<grpc::ClientContext> context = As(token);
      return call(context.get()).error_code();
    };
    v1::Job job;
    v1::Mesh mesh;
    EXPECT_EQ(
        code([&](grpc::ClientContext* c) { return stub_->SubmitJob(c, NotchRequest(), &job); }),
        grpc::StatusCode::UNAUTHENTICATED);
    v1::CreateMeshRequest create;
    *create.mutable_mesh() = NotchRequest().mesh();
    EXPECT_EQ(code([&](grpc::ClientContext* c) { return stub_->CreateMesh(c, create, &mesh); }),
              grpc::StatusCode::UNAUTHENTICATED);
    EXPECT_EQ(
        code([&](grpc::ClientContext* c) { return stub_->GetJob(c, v1::GetJobRequest(), &job); }),
        grpc::StatusCode::UNAUTHENTICATED);
    v1::ListJobsResponse list;
    EXPECT_EQ(code([&](grpc::ClientContext* c) {
                return stub_->ListJobs(c, v1::ListJobsRequest(), &list);
              }),
              grpc::StatusCode::UNAUTHENTICATED);
    EXPECT_EQ(code([&](grpc::ClientContext* c) {
                return stub_->CancelJob(c, v1::CancelJobRequest(), &job);
              }),
              grpc::StatusCode::UNAUTHENTICATED);
    EXPECT_EQ(code([&](grpc::ClientContext* c) {
                return stub_->GetMesh(c, v1::GetMeshRequest(), &mesh);
              }),
              grpc::StatusCode::UNAUTHENTICATED);
    v1::DeleteMeshResponse deleted;
    EXPECT_EQ(code([&](grpc::ClientContext* c) {
                return stub_->DeleteMesh(c, v1::DeleteMeshRequest(), &deleted);
              }),
              grpc::StatusCode::UNAUTHENTICATED);
    v1::ServerStats stats;
    EXPECT_EQ(code([&](grpc::ClientContext* c) {
                return stub_->GetServerStats(c, v1::GetServerStatsRequest(), &stats);
              }),
              grpc::StatusCode::UNAUTHENTICATED);

    std::unique_ptr<grpc::ClientContext> quantize = As(token);
    const ReadStream quantized = ReadAll(*stub_->Quantize(quantize.get(), NotchRequest()));
    EXPECT_EQ(quantized.status.error_code(), grpc::StatusCode::UNAUTHENTICATED);
    EXPECT_TRUE(quantized.events.empty());
    std::unique_ptr<grpc::ClientContext> watch = As(token);
    const ReadStream watched = ReadAll(*stub_->WatchJob(watch.get(), v1::WatchJobRequest()));
    EXPECT_EQ(watched.status.error_code(), grpc::StatusCode::UNAUTHENTICATED);
    EXPECT_TRUE(watched.events.empty());
  }
  EXPECT_EQ(job_service_.Stats().accepted_total(), 0) << "no refused call made a job";
}

// The methods are registered raw so that the service, not gRPC, answers a request that does not
// parse; a caller learns of its bytes only once authenticated.
TEST_F(QuantizerServiceTest, BytesThatAreNoRequestAreInvalidArgumentNamingTheType) {
  const std::string garbage("\x00\x01\x02", 3);
  for (const auto& [method, type] :
       std::map<std::string, std::string>{{"GetJob", "ispq.v1.GetJobRequest"},
                                          {"ListJobs", "ispq.v1.ListJobsRequest"},
                                          {"GetServerStats", "ispq.v1.GetServerStatsRequest"},
                                          {"SubmitJob", "ispq.v1.QuantizeRequest"},
                                          {"CreateMesh", "ispq.v1.CreateMeshRequest"}}) {
    SCOPED_TRACE(method);
    const grpc::Status status = RawCall(method, garbage);
    EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
    EXPECT_THAT(status.error_message(), HasSubstr(type));
    EXPECT_EQ(RawCall(method, garbage, /*token=*/"").error_code(),
              grpc::StatusCode::UNAUTHENTICATED);
  }
}

TEST_F(QuantizerServiceTest, LookupsLargerThanAnyRealOneAreRefused) {
  v1::GetJobRequest get;
  get.set_name("jobs/" + std::string(70 << 10, 'a'));
  v1::Job job;
  const grpc::Status status = stub_->GetJob(As(kAliceToken).get(), get, &job);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_THAT(status.error_message(), HasSubstr("accepts at most 65536"));

  v1::WatchJobRequest watch;
  watch.set_name(get.name());
  std::unique_ptr<grpc::ClientContext> context = As(kAliceToken);
  EXPECT_EQ(ReadAll(*stub_->WatchJob(context.get(), watch)).status.error_code(),
            grpc::StatusCode::INVALID_ARGUMENT);
}

TEST_F(QuantizerServiceTest, TheServicesErrorsReachTheClientWithTheirCodes) {
  const std::string unknown = "jobs/0000000000000000";
  v1::Job job;
  v1::GetJobRequest get;
  get.set_name(unknown);
  EXPECT_EQ(stub_->GetJob(As(kAliceToken).get(), get, &job).error_code(),
            grpc::StatusCode::NOT_FOUND);
  get.set_name("not a name");
  EXPECT_EQ(stub_->GetJob(As(kAliceToken).get(), get, &job).error_code(),
            grpc::StatusCode::INVALID_ARGUMENT);
  v1::CancelJobRequest cancel;
  cancel.set_name(unknown);
  EXPECT_EQ(stub_->CancelJob(As(kAliceToken).get(), cancel, &job).error_code(),
            grpc::StatusCode::NOT_FOUND);
  v1::DeleteMeshRequest remove;
  remove.set_name("meshes/0000000000000000");
  v1::DeleteMeshResponse deleted;
  EXPECT_EQ(stub_->DeleteMesh(As(kAliceToken).get(), remove, &deleted).error_code(),
            grpc::StatusCode::NOT_FOUND);
  v1::WatchJobRequest watch;
  watch.set_name(unknown);
  std::unique_ptr<grpc::ClientContext> context = As(kAliceToken);
  const ReadStream watched = ReadAll(*stub_->WatchJob(context.get(), watch));
  EXPECT_EQ(watched.status.error_code(), grpc::StatusCode::NOT_FOUND);
  EXPECT_TRUE(watched.events.empty());

  v1::QuantizeRequest invalid = NotchRequest();
  invalid.mutable_mesh()->mutable_arcs(3)->set_length(-1);
  const grpc::Status refused = stub_->SubmitJob(As(kAliceToken).get(), invalid, &job);
  EXPECT_EQ(refused.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_THAT(refused.error_message(), HasSubstr("arc 3"));
  std::unique_ptr<grpc::ClientContext> quantize = As(kAliceToken);
  EXPECT_EQ(ReadAll(*stub_->Quantize(quantize.get(), invalid)).status.error_code(),
            grpc::StatusCode::INVALID_ARGUMENT);
}

// A full queue (no workers, two places) refuses with a hint when to retry: the trailer that gRPC
// clients with a retry policy honour, on SubmitJob's answer and on Quantize's stream.
TEST_F(QuantizerServiceTest, ARetryHintBecomesTheRetryTrailer) {
  v1::Job job;
  for (int i = 0; i < 2; ++i) {
    ASSERT_TRUE(stub_->SubmitJob(As(kAliceToken).get(), NotchRequest(), &job).ok());
  }
  std::unique_ptr<grpc::ClientContext> submit = As(kAliceToken);
  const grpc::Status full = stub_->SubmitJob(submit.get(), NotchRequest(), &job);
  EXPECT_EQ(full.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
  const std::string hint = RetryTrailer(*submit);
  EXPECT_FALSE(hint.empty());
  EXPECT_THAT(full.error_message(), HasSubstr("retry in " + hint + " ms"));

  std::unique_ptr<grpc::ClientContext> quantize = As(kAliceToken);
  const ReadStream quantized = ReadAll(*stub_->Quantize(quantize.get(), NotchRequest()));
  EXPECT_EQ(quantized.status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
  EXPECT_FALSE(RetryTrailer(*quantize).empty());

  // Errors without a hint carry no trailer.
  v1::GetJobRequest get;
  get.set_name("jobs/0000000000000000");
  std::unique_ptr<grpc::ClientContext> lookup = As(kAliceToken);
  EXPECT_EQ(stub_->GetJob(lookup.get(), get, &job).error_code(), grpc::StatusCode::NOT_FOUND);
  EXPECT_EQ(RetryTrailer(*lookup), "");
}

// One pass through every method, each answered by its own operation as the token's principal;
// afterwards no request or response is held in the memory budget.
TEST_F(QuantizerServiceTest, EachMethodReachesItsOperationAsTheTokensPrincipal) {
  v1::CreateMeshRequest create;
  *create.mutable_mesh() = NotchRequest().mesh();
  v1::Mesh mesh;
  ASSERT_TRUE(stub_->CreateMesh(As(kAliceToken).get(), create, &mesh).ok());
  EXPECT_EQ(mesh.owner(), "alice");
  v1::GetMeshRequest get_mesh;
  get_mesh.set_name(mesh.name());
  v1::Mesh got_mesh;
  ASSERT_TRUE(stub_->GetMesh(As(kAliceToken).get(), get_mesh, &got_mesh).ok());
  EXPECT_EQ(got_mesh.name(), mesh.name());

  v1::QuantizeRequest on_stored = NotchRequest();
  on_stored.set_stored_mesh(mesh.name());
  v1::Job submitted;
  ASSERT_TRUE(stub_->SubmitJob(As(kAliceToken).get(), on_stored, &submitted).ok());
  EXPECT_EQ(submitted.owner(), "alice");
  EXPECT_EQ(submitted.stored_mesh(), mesh.name());
  EXPECT_EQ(submitted.state(), v1::QUEUED);

  v1::GetJobRequest get;
  get.set_name(submitted.name());
  v1::Job got;
  ASSERT_TRUE(stub_->GetJob(As(kAliceToken).get(), get, &got).ok());
  EXPECT_EQ(got.name(), submitted.name());
  v1::ListJobsResponse listed;
  ASSERT_TRUE(stub_->ListJobs(As(kAliceToken).get(), v1::ListJobsRequest(), &listed).ok());
  ASSERT_EQ(listed.jobs_size(), 1);
  EXPECT_EQ(listed.jobs(0).name(), submitted.name());

  v1::WatchJobRequest watch;
  watch.set_name(submitted.name());
  std::unique_ptr<grpc::ClientContext> watch_context = As(kAliceToken);
  auto watcher = stub_->WatchJob(watch_context.get(), watch);
  v1::QuantizeEvent accepted;
  ASSERT_TRUE(watcher->Read(&accepted));
  EXPECT_TRUE(accepted.has_accepted());
  v1::CancelJobRequest cancel;
  cancel.set_name(submitted.name());
  v1::Job cancelled;
  ASSERT_TRUE(stub_->CancelJob(As(kAliceToken).get(), cancel, &cancelled).ok());
  EXPECT_EQ(cancelled.state(), v1::CANCELLED);
  const ReadStream rest = ReadAll(*watcher);
  EXPECT_EQ(rest.status.error_code(), grpc::StatusCode::CANCELLED);

  v1::ServerStats stats;
  ASSERT_TRUE(
      stub_->GetServerStats(As(kAliceToken).get(), v1::GetServerStatsRequest(), &stats).ok());
  EXPECT_EQ(stats.accepted_total(), 1);
  EXPECT_EQ(stats.stored_meshes(), 1);
  EXPECT_EQ(stats.finished_total().cancelled(), 1);

  v1::DeleteMeshRequest remove;
  remove.set_name(mesh.name());
  v1::DeleteMeshResponse deleted;
  ASSERT_TRUE(stub_->DeleteMesh(As(kAliceToken).get(), remove, &deleted).ok());
  EXPECT_EQ(stub_->GetMesh(As(kAliceToken).get(), get_mesh, &got_mesh).error_code(),
            grpc::StatusCode::NOT_FOUND);

  EXPECT_TRUE(testing::WaitUntil([&] {
    return budget_.used(MemoryUse::kRequests) == 0 && budget_.used(MemoryUse::kResponses) == 0;
  })) << "requests "
      << budget_.used(MemoryUse::kRequests) << " B, responses "
      << budget_.used(MemoryUse::kResponses) << " B still held";
  EXPECT_GT(budget_.ToProto().peak_used_bytes(), 0);
}

}  // namespace
}  // namespace ispq::server
