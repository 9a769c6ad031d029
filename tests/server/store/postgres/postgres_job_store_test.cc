// SPDX-License-Identifier: Apache-2.0
// What PostgresJobStore (server/store/postgres/postgres_job_store.h) does beyond the store
// contract (job_store_test.cc) and the claims between replicas (postgres_job_claims_test.cc):
// its options, Lookup while the database is gone, the stored request a claim carries, the end
// of call-bound jobs whose replica died, wake-ups for queued work, Fail, and a cancellation that
// came before a run was adopted.
#include "server/store/postgres/postgres_job_store.h"

#include <unistd.h>

#include <atomic>
#include <memory>
#include <optional>
#include <string>

#include "absl/strings/str_cat.h"
#include "google/protobuf/util/message_differencer.h"
#include "gtest/gtest.h"
#include "tests/server/server_test_jobs.h"
#include "tests/support/bounded_wait.h"
#include "tests/support/postgres_suite.h"

namespace ispq::server {
namespace {

using ::ispq::testing::WaitUntil;

constexpr absl::Duration kLease = absl::Milliseconds(600);

class PostgresJobStoreTest : public ispq::testing::PostgresSuite {
 protected:
  void SetUp() override {
    database_ = absl::StrCat("store", next_database_++);
    absl::StatusOr<std::string> uri = postgres_->CreateDatabase(database_);
    ASSERT_TRUE(uri.ok()) << uri.status();
    uri_ = *uri;
  }

  PostgresJobStoreOptions Options(const std::string& replica, absl::Duration lease = kLease) {
    PostgresJobStoreOptions options;
    options.uri = uri_;
    options.lease = lease;
    options.replica = replica;
    options.probe_period = absl::Milliseconds(50);
    return options;
  }
  std::unique_ptr<PostgresJobStore> Replica(const std::string& name,
                                            absl::Duration lease = kLease) {
    absl::StatusOr<std::unique_ptr<PostgresJobStore>> store =
        PostgresJobStore::Open(Options(name, lease));
    EXPECT_TRUE(store.ok()) << store.status();
    return store.ok() ? *std::move(store) : nullptr;
  }

  // Claims the next job on `replica` and adopts a run of it there, not started.
  static std::shared_ptr<Job> ClaimAndAdopt(PostgresJobStore& replica,
                                            JobClaims::Claim* claimed = nullptr) {
    std::optional<JobClaims::Claim> claim = replica.ClaimNext();
    if (!claim.has_value()) return nullptr;
    std::shared_ptr<Job> runner = Job::Resume(claim->id, NotchJobSpec(), false, claim->create_time,
                                              claim->next_sequence, nullptr);
    replica.Adopt(runner, *claim);
    if (claimed != nullptr) *claimed = *claim;
    return runner;
  }

  std::string database_;
  std::string uri_;
};

TEST_F(PostgresJobStoreTest, OpenRefusesAShortLeaseAndANewerSchemaAndNamesTheReplica) {
  EXPECT_EQ(PostgresJobStore::Open(Options("a", absl::Milliseconds(299))).status().code(),
            absl::StatusCode::kInvalidArgument);
  absl::StatusOr<std::unique_ptr<PostgresJobStore>> unnamed = PostgresJobStore::Open(Options(""));
  ASSERT_TRUE(unnamed.ok()) << unnamed.status();
  EXPECT_NE((*unnamed)->replica().find(absl::StrCat("/", getpid(), "/")), std::string::npos)
      << (*unnamed)->replica();
  EXPECT_TRUE((*unnamed)->shared());
  unnamed->reset();
  ASSERT_TRUE(postgres_->Sql("UPDATE ispq_schema SET version = version + 1", database_).ok());
  EXPECT_EQ(PostgresJobStore::Open(Options("a")).status().code(),
            absl::StatusCode::kFailedPrecondition);
}

// A client must never be told that a job does not exist when the store could not say.
TEST_F(PostgresJobStoreTest, LookupTellsAnUnknownJobFromADatabaseThatDoesNotAnswer) {
  std::unique_ptr<PostgresJobStore> store = Replica("a");
  ASSERT_TRUE(store->Add(NewNotchJob("known"), "", absl::Now()).ok());
  absl::StatusOr<std::shared_ptr<Job>> unknown = store->Lookup("unknown", absl::Now());
  ASSERT_TRUE(unknown.ok()) << unknown.status();
  EXPECT_EQ(*unknown, nullptr);
  EXPECT_TRUE(store->reachable());
  ASSERT_TRUE(
      postgres_->Sql(absl::StrCat("DROP DATABASE ", database_, " WITH (FORCE)"), "postgres").ok());
  EXPECT_EQ(store->Lookup("known", absl::Now()).status().code(), absl::StatusCode::kUnavailable);
  EXPECT_EQ(store->Find("known", absl::Now()), nullptr);
  EXPECT_EQ(store->Add(NewNotchJob("new"), "", absl::Now()).status().code(),
            absl::StatusCode::kUnavailable);
  EXPECT_EQ(store->QueuedCount(), -1);
  EXPECT_TRUE(WaitUntil([&] { return !store->reachable(); }));
}

// Any replica can run a job: the request it was admitted from is stored with it. One whose
// stored request cannot be read ends rather than blocking the queue.
TEST_F(PostgresJobStoreTest, AClaimCarriesTheStoredRequestAndAnUnreadableOneEndsTheJob) {
  std::unique_ptr<PostgresJobStore> a = Replica("a");
  std::unique_ptr<PostgresJobStore> b = Replica("b");
  v1::QuantizeRequest request;
  request.set_stored_mesh("meshes/m1");
  request.mutable_options()->set_per_arc_nonnegative(true);
  const std::string bytes = request.SerializeAsString();
  ASSERT_TRUE(a->Add(NewNotchJob("unreadable"), "\xff\xff\xff", absl::Now()).ok());
  ASSERT_TRUE(a->Add(NewNotchJob("readable"), bytes, absl::Now()).ok());
  EXPECT_FALSE(b->ClaimNext().has_value()) << "the unreadable one, ended instead";
  std::shared_ptr<Job> unreadable = b->Find("unreadable", absl::Now());
  ASSERT_NE(unreadable, nullptr);
  EXPECT_EQ(unreadable->state(), v1::FAILED);
  EXPECT_EQ(unreadable->ToProto(v1::BASIC).error().code(),
            static_cast<int32_t>(absl::StatusCode::kInternal));
  std::optional<JobClaims::Claim> claim = b->ClaimNext();
  ASSERT_TRUE(claim.has_value());
  EXPECT_EQ(claim->id, "readable");
  EXPECT_TRUE(google::protobuf::util::MessageDifferencer::Equals(claim->request, request));
  EXPECT_EQ(claim->request_bytes, static_cast<int64_t>(bytes.size()));
  EXPECT_EQ(claim->owner, NotchJobSpec().owner);
}

// A Quantize call's job runs on its replica only; when that replica stops renewing for a whole
// lease beyond the expiry, another replica ends it (the call died with its replica).
TEST_F(PostgresJobStoreTest, ACallBoundJobWhoseReplicaDiedIsEndedUnavailable) {
  constexpr absl::Duration kShortLease = absl::Milliseconds(300);
  std::unique_ptr<PostgresJobStore> a = Replica("a", kShortLease);
  std::unique_ptr<PostgresJobStore> b = Replica("b", kShortLease);
  auto call = std::make_shared<Job>("call", NotchJobSpec(), /*bound_to_call=*/true, 0, absl::Now());
  ASSERT_TRUE(a->Add(call, "", absl::Now()).ok());
  ASSERT_TRUE(call->Start(absl::Now()));
  ASSERT_TRUE(a->Flush(absl::Now() + ispq::testing::kSafetyNet));
  EXPECT_FALSE(b->ClaimNext().has_value()) << "never claimed by another replica";
  a.reset();  // dies mid-run
  std::shared_ptr<Job> seen;
  ASSERT_TRUE(WaitUntil([&] {
    seen = b->Find("call", absl::Now());
    return seen != nullptr && seen->done();
  }));
  EXPECT_EQ(seen->state(), v1::FAILED);
  EXPECT_EQ(seen->ToProto(v1::BASIC).error().code(),
            static_cast<int32_t>(absl::StatusCode::kUnavailable));
}

TEST_F(PostgresJobStoreTest, AJobQueuedOnAnotherReplicaWakesThisOnesWorkers) {
  std::atomic<int> woken = 0;  // outlives the stores, whose threads wake
  std::unique_ptr<PostgresJobStore> a = Replica("a");
  std::unique_ptr<PostgresJobStore> b = Replica("b");
  b->OnClaimable([&woken] { ++woken; });
  ASSERT_TRUE(a->Add(NewNotchJob("queued"), "", absl::Now()).ok());
  EXPECT_TRUE(WaitUntil([&] { return woken > 0; }));
  EXPECT_EQ(b->QueuedCount(), 1);
}

// A job that can never run is ended by the replica holding its claim, and by no other.
TEST_F(PostgresJobStoreTest, FailEndsAClaimedJobUnlessTheClaimWasSuperseded) {
  std::unique_ptr<PostgresJobStore> a = Replica("a");
  std::unique_ptr<PostgresJobStore> b = Replica("b");
  ASSERT_TRUE(a->Add(NewNotchJob("j"), "", absl::Now()).ok());
  std::optional<JobClaims::Claim> stale = a->ClaimNext();
  ASSERT_TRUE(stale.has_value());
  ASSERT_TRUE(
      postgres_->Sql("UPDATE ispq_jobs SET lease_expires = now() - interval '1 hour'", database_)
          .ok());
  std::optional<JobClaims::Claim> current = b->ClaimNext();
  ASSERT_TRUE(current.has_value());
  a->Fail(*stale, absl::InvalidArgumentError("stale"));
  EXPECT_EQ(b->Find("j", absl::Now())->state(), v1::RUNNING);
  b->Fail(*current, absl::InvalidArgumentError("the mesh no longer admits"));
  std::shared_ptr<Job> ended = a->Find("j", absl::Now());
  ASSERT_NE(ended, nullptr);
  EXPECT_EQ(ended->state(), v1::FAILED);
  EXPECT_EQ(ended->ToProto(v1::BASIC).error().message(), "the mesh no longer admits");
}

// Cancelled between the claim and the adoption, when no run here could be told (here the notice
// is not even sent): adopting looks, and the run does not start.
TEST_F(PostgresJobStoreTest, ACancellationBeforeTheRunWasAdoptedStillStopsIt) {
  std::unique_ptr<PostgresJobStore> a = Replica("a");
  std::unique_ptr<PostgresJobStore> b = Replica("b");
  ASSERT_TRUE(a->Add(NewNotchJob("j"), "", absl::Now()).ok());
  std::optional<JobClaims::Claim> claim = a->ClaimNext();
  ASSERT_TRUE(claim.has_value());
  EXPECT_FALSE(claim->cancel_requested);
  ASSERT_TRUE(postgres_->Sql("UPDATE ispq_jobs SET cancel_requested = true", database_).ok());
  std::shared_ptr<Job> runner = Job::Resume(claim->id, NotchJobSpec(), false, claim->create_time,
                                            claim->next_sequence, nullptr);
  a->Adopt(runner, *claim);
  EXPECT_FALSE(runner->Start(absl::Now()));
  EXPECT_TRUE(runner->interrupter().IsInterrupted());
  EXPECT_EQ(a->ActiveJobs().size(), 1u) << "adopted here until it ends";
  EXPECT_TRUE(b->ActiveJobs().empty());
}

}  // namespace
}  // namespace ispq::server
