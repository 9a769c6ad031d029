// SPDX-License-Identifier: Apache-2.0
// Idempotent SubmitJob (AIP-155, issue 7): a retried SubmitJob with the same request_id returns
// the job the first call created, whether that call's answer was lost to a short deadline or
// not; the same id with a different request is ALREADY_EXISTS; ids are per principal. Before
// request_id, a 1 ms deadline created the job in about half the tries (78 of 162), so a client
// that retried created duplicates.
#include <memory>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "absl/strings/str_cat.h"
#include "absl/time/clock.h"
#include "gmock/gmock.h"
#include "grpcpp/client_context.h"
#include "gtest/gtest.h"
#include "ispq/v1/service.grpc.pb.h"
#include "tests/integration/service_test_support.h"
#include "tests/support/run_command.h"
#include "tests/support/tmesh_copies.h"

namespace ispq::testing {
namespace {

using ::testing::HasSubstr;

v1::QuantizeRequest WithId(v1::QuantizeRequest request, const std::string& request_id) {
  request.set_request_id(request_id);
  return request;
}

// A SubmitJob whose deadline passes before the answer can arrive; the job may or may not exist.
grpc::Status SubmitWithDeadline(client::QuantizerClient& client, const v1::QuantizeRequest& request,
                                absl::Duration timeout) {
  std::unique_ptr<v1::Quantizer::Stub> stub = v1::Quantizer::NewStub(client.channel());
  grpc::ClientContext context;
  context.set_deadline(absl::ToChronoTime(absl::Now() + timeout));
  v1::Job job;
  return stub->SubmitJob(&context, request, &job);
}

// Every job the server retains, by name.
std::set<std::string> AllJobs(client::QuantizerClient& client) {
  v1::ListJobsRequest list;
  list.set_page_size(1000);
  const absl::StatusOr<v1::ListJobsResponse> page = client.ListJobs(list);
  EXPECT_TRUE(page.ok()) << page.status();
  std::set<std::string> names;
  if (page.ok()) {
    for (const v1::Job& job : page->jobs()) names.insert(job.name());
  }
  return names;
}

// Waits for every job in `names` and checks its result with the validator.
void ExpectValidResults(client::QuantizerClient& client, const std::set<std::string>& names,
                        const v1::TMesh& mesh) {
  for (const std::string& name : names) {
    const absl::StatusOr<v1::Job> done = WaitUntilDone(client, name);
    ASSERT_TRUE(done.ok()) << done.status();
    ASSERT_EQ(done->state(), v1::SUCCEEDED) << name;
    EXPECT_TRUE(IsValidResult(mesh, done->result())) << name;
  }
}

TEST(IdempotencyTest, ARetryWithTheSameIdReturnsTheSameJob) {
  std::unique_ptr<ServerProcess> server = StartServerOrFail({});
  ASSERT_NE(server, nullptr);
  client::QuantizerClient client = ClientOf(*server);
  const v1::QuantizeRequest request = WithId(RequestFor(NotchMesh(), 100), "8d6f2a1e-5b4c");
  const absl::StatusOr<v1::Job> first = client.SubmitJob(request);
  ASSERT_TRUE(first.ok()) << first.status();
  EXPECT_EQ(first->request_id(), "8d6f2a1e-5b4c");
  const absl::StatusOr<v1::Job> retried = client.SubmitJob(request);
  ASSERT_TRUE(retried.ok()) << retried.status();
  EXPECT_EQ(retried->name(), first->name());
  // Also after the job has ended: the retry sees it as it is now.
  ASSERT_TRUE(WaitUntilDone(client, first->name()).ok());
  const absl::StatusOr<v1::Job> late = client.SubmitJob(request);
  ASSERT_TRUE(late.ok()) << late.status();
  EXPECT_EQ(late->name(), first->name());
  EXPECT_TRUE(late->done());
  EXPECT_EQ(AllJobs(client).size(), 1u);
  ExpectValidResults(client, {first->name()}, NotchMesh());
  // Without an id, every call is a new job.
  const absl::StatusOr<v1::Job> anonymous = client.SubmitJob(RequestFor(NotchMesh(), 100));
  ASSERT_TRUE(anonymous.ok()) << anonymous.status();
  EXPECT_NE(anonymous->name(), first->name());
  ExpectValidResults(client, {anonymous->name()}, NotchMesh());
}

TEST(IdempotencyTest, TheSameIdWithADifferentRequestIsAlreadyExists) {
  std::unique_ptr<ServerProcess> server = StartServerOrFail({});
  ASSERT_NE(server, nullptr);
  client::QuantizerClient client = ClientOf(*server);
  const absl::StatusOr<v1::Job> first =
      client.SubmitJob(WithId(RequestFor(NotchMesh(), 100), "reused-id"));
  ASSERT_TRUE(first.ok()) << first.status();
  const absl::StatusOr<v1::Job> other =
      client.SubmitJob(WithId(RequestFor(NotchMesh(), 50), "reused-id"));
  EXPECT_EQ(other.status().code(), absl::StatusCode::kAlreadyExists) << other.status();
  EXPECT_THAT(std::string(other.status().message()),
              HasSubstr("request_id reused-id was already used for a different request"));
  EXPECT_EQ(AllJobs(client).size(), 1u);
  ExpectValidResults(client, {first->name()}, NotchMesh());

  const absl::StatusOr<v1::Job> malformed =
      client.SubmitJob(WithId(RequestFor(NotchMesh(), 100), "no spaces/or slashes"));
  EXPECT_EQ(malformed.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(malformed.status().message()), HasSubstr("request_id must be"));
  const client::JobOutcome streamed = client.Quantize(
      WithId(RequestFor(NotchMesh(), 100), "a-quantize-id"), StreamFor(kJobTimeout));
  EXPECT_EQ(streamed.status.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(streamed.status.message()), HasSubstr("request_id is for SubmitJob"));
  EXPECT_TRUE(streamed.job.empty());
}

TEST(IdempotencyTest, RetriesAfterShortDeadlinesCreateNoDuplicates) {
  std::unique_ptr<ServerProcess> server = StartServerOrFail({"--workers=2"});
  ASSERT_NE(server, nullptr);
  client::QuantizerClient client = ClientOf(*server);
  // Ten copies of the sample (about 1 MB): admitted in a few milliseconds, more than the first
  // try's deadline, so that its answer is lost while the job may well be created.
  const v1::TMesh mesh = DisjointCopies(NotchMesh(), 10);
  constexpr int kRequests = 60;
  std::set<std::string> jobs;
  int deadline_exceeded = 0;
  for (int i = 0; i < kRequests; ++i) {
    const v1::QuantizeRequest request =
        WithId(RequestFor(mesh, 100), absl::StrCat("short-deadline-", i));
    deadline_exceeded += SubmitWithDeadline(client, request, absl::Milliseconds(1)).error_code() ==
                         grpc::StatusCode::DEADLINE_EXCEEDED;
    // The client retries until it has an answer, as a client with a retry policy does.
    absl::StatusOr<v1::Job> job = client.SubmitJob(request);
    for (int attempt = 0; !job.ok() && attempt < 10; ++attempt) job = client.SubmitJob(request);
    ASSERT_TRUE(job.ok()) << job.status();
    jobs.insert(job->name());
  }
  std::cout << deadline_exceeded << " of " << kRequests << " first tries passed their deadline\n";
  EXPECT_GT(deadline_exceeded, 0) << "the test did not exercise lost answers";
  EXPECT_EQ(jobs.size(), static_cast<size_t>(kRequests));
  EXPECT_EQ(AllJobs(client), jobs) << "a job for every id, and no other";
  const absl::StatusOr<v1::ServerStats> stats = client.GetServerStats();
  ASSERT_TRUE(stats.ok());
  EXPECT_EQ(stats->accepted_total(), kRequests);
  ExpectValidResults(client, jobs, mesh);
}

TEST(IdempotencyTest, ConcurrentCallsWithOneIdMakeOneJob) {
  std::unique_ptr<ServerProcess> server = StartServerOrFail({"--workers=1"});
  ASSERT_NE(server, nullptr);
  // Large enough to be admitted off gRPC's threads, so the calls overlap while it is parsed.
  const v1::TMesh mesh = MeshTakingSeconds(2);
  const v1::QuantizeRequest request = WithId(RequestFor(mesh, 100), "one-id-many-calls");
  std::vector<std::string> names(8);
  std::vector<std::thread> threads;
  for (int i = 0; i < 8; ++i) {
    threads.emplace_back([&, i] {
      client::QuantizerClient own = ClientOf(*server);
      const absl::StatusOr<v1::Job> job = own.SubmitJob(request);
      ASSERT_TRUE(job.ok()) << job.status();
      names[i] = job->name();
    });
  }
  for (std::thread& thread : threads) thread.join();
  const std::set<std::string> distinct(names.begin(), names.end());
  EXPECT_EQ(distinct.size(), 1u);
  client::QuantizerClient client = ClientOf(*server);
  EXPECT_EQ(AllJobs(client), distinct);
  ExpectValidResults(client, distinct, mesh);
}

TEST(IdempotencyTest, IdsBelongToTheirPrincipal) {
  const std::string directory = ::testing::TempDir();
  const std::string tokens = directory + "/idempotency-tokens";
  ASSERT_EQ(RunCommand("printf 'alice alice-token\\nbob bob-token\\n' > " + tokens).exit_code, 0);
  std::unique_ptr<ServerProcess> server = StartServerOrFail({"--auth_tokens_file=" + tokens});
  ASSERT_NE(server, nullptr);
  client::QuantizerClient alice = ClientOf(*server, "alice-token");
  client::QuantizerClient bob = ClientOf(*server, "bob-token");
  const v1::QuantizeRequest request = WithId(RequestFor(NotchMesh(), 100), "shared-id");
  const absl::StatusOr<v1::Job> of_alice = alice.SubmitJob(request);
  const absl::StatusOr<v1::Job> of_bob = bob.SubmitJob(request);
  ASSERT_TRUE(of_alice.ok()) << of_alice.status();
  ASSERT_TRUE(of_bob.ok()) << of_bob.status();
  EXPECT_NE(of_alice->name(), of_bob->name());
  ExpectValidResults(alice, {of_alice->name()}, NotchMesh());
  ExpectValidResults(bob, {of_bob->name()}, NotchMesh());
}

}  // namespace
}  // namespace ispq::testing
