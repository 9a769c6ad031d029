// SPDX-License-Identifier: Apache-2.0
// The PostgreSQL job store as several replicas see it: two stores on one real database stand for
// two replicas. Claims, lease expiry, cross-replica watching, request ids and cancellation.
#include <fstream>
#include <iostream>
#include <iterator>
#include <memory>
#include <optional>
#include <string>

#include "absl/strings/ascii.h"
#include "absl/strings/str_cat.h"
#include "absl/synchronization/notification.h"
#include "gtest/gtest.h"
#include "server/store/postgres/postgres_job_store.h"
#include "tests/server/server_test_jobs.h"
#include "tests/support/bounded_wait.h"
#include "tests/support/postgres_suite.h"

namespace ispq::server {
namespace {

using ::ispq::testing::kSafetyNet;
using ::ispq::testing::WaitUntil;

constexpr absl::Duration kLease = absl::Milliseconds(600);

class PostgresJobClaimsTest : public ispq::testing::PostgresSuite {
 protected:
  void SetUp() override {
    absl::StatusOr<std::string> uri =
        postgres_->CreateDatabase(absl::StrCat("claims", next_database_++));
    ASSERT_TRUE(uri.ok()) << uri.status();
    uri_ = *uri;
  }

  std::unique_ptr<PostgresJobStore> Replica(const std::string& name,
                                            absl::Duration lease = kLease) {
    PostgresJobStoreOptions options;
    options.uri = uri_;
    options.lease = lease;
    options.replica = name;
    absl::StatusOr<std::unique_ptr<PostgresJobStore>> store = PostgresJobStore::Open(options);
    EXPECT_TRUE(store.ok()) << store.status();
    return store.ok() ? *std::move(store) : nullptr;
  }

  static std::shared_ptr<Job> JobWithRequestId(const std::string& id, const std::string& request_id,
                                               const std::string& fingerprint) {
    JobSpec spec = NotchJobSpec();
    spec.request_id = request_id;
    spec.request_fingerprint = fingerprint;
    return std::make_shared<Job>(id, std::move(spec), false, 0, absl::Now());
  }

  // Claims the next job on `replica` and starts running it there, as a worker does; null if
  // there is none.
  static std::shared_ptr<Job> ClaimAndRun(PostgresJobStore& replica,
                                          JobClaims::Claim* claimed = nullptr) {
    std::optional<JobClaims::Claim> claim = replica.ClaimNext();
    if (!claim.has_value()) return nullptr;
    std::shared_ptr<Job> runner = Job::Resume(claim->id, NotchJobSpec(), false, claim->create_time,
                                              claim->next_sequence, nullptr);
    replica.Adopt(runner, *claim);
    if (!runner->Start(absl::Now())) return nullptr;
    if (claimed != nullptr) *claimed = *claim;
    return runner;
  }

  // Expires every lease at once and claims on `replica`, as if the lease holder had stalled;
  // tried again if the holder renewed its lease in between.
  std::shared_ptr<Job> TakeOver(PostgresJobStore& replica, JobClaims::Claim* claimed = nullptr) {
    for (int attempt = 0; attempt < 50; ++attempt) {
      if (!postgres_
               ->Sql("UPDATE ispq_jobs SET lease_expires = now() - interval '1 hour' WHERE "
                     "state = 2",
                     Database())
               .ok()) {
        return nullptr;
      }
      if (std::shared_ptr<Job> runner = ClaimAndRun(replica, claimed)) return runner;
    }
    return nullptr;
  }

  // The job's row as `state|attempts|lease owner`.
  std::string Row(const std::string& id) {
    absl::StatusOr<std::string> row = postgres_->Sql(
        absl::StrCat("SELECT state || '|' || attempts || '|' || coalesce(lease_owner, '') FROM "
                     "ispq_jobs WHERE id = '",
                     id, "'"),
        Database());
    return row.ok() ? std::string(absl::StripAsciiWhitespace(*row)) : row.status().ToString();
  }
  std::string Database() const { return uri_.substr(uri_.rfind('/') + 1); }

  std::string uri_;
};

class CountingWatcher : public JobWatcher {
 public:
  explicit CountingWatcher(const Job& job) : job_(job) {}
  void OnJobEvent() override {
    if (job_.done() && !ended_.HasBeenNotified()) ended_.Notify();
  }
  absl::Notification ended_;

 private:
  const Job& job_;
};

TEST_F(PostgresJobClaimsTest, EachQueuedJobIsClaimedOnceOldestFirst) {
  std::unique_ptr<PostgresJobStore> a = Replica("a");
  std::unique_ptr<PostgresJobStore> b = Replica("b");
  ASSERT_TRUE(a->Add(NewNotchJob("first"), "", absl::Now()).ok());
  ASSERT_TRUE(a->Add(NewNotchJob("second"), "", absl::Now()).ok());
  EXPECT_EQ(a->QueuedCount(), 2);
  std::optional<JobClaims::Claim> one = b->ClaimNext();
  std::optional<JobClaims::Claim> two = a->ClaimNext();
  ASSERT_TRUE(one.has_value() && two.has_value());
  EXPECT_EQ(one->id, "first");
  EXPECT_EQ(two->id, "second");
  EXPECT_EQ(one->attempt, 1);
  EXPECT_EQ(one->next_sequence, 1) << "after the accepted event";
  EXPECT_FALSE(b->ClaimNext().has_value());
  EXPECT_EQ(a->Find("first", absl::Now())->state(), v1::RUNNING);
}

TEST_F(PostgresJobClaimsTest, AJobWhoseReplicaDiedIsClaimedAgainAfterItsLease) {
  // Long enough that the lease still holds when a asks right after b's claim, unless the
  // machine stalls for seconds (checked, not assumed).
  constexpr absl::Duration kLongLease = absl::Seconds(2);
  std::unique_ptr<PostgresJobStore> a = Replica("a", kLongLease);
  std::unique_ptr<PostgresJobStore> b = Replica("b", kLongLease);
  ASSERT_TRUE(a->Add(NewNotchJob("orphan"), "", absl::Now()).ok());
  // The lease runs from b's claim, which happens after `before_claim`.
  const absl::Time before_claim = absl::Now();
  ASSERT_TRUE(b->ClaimNext().has_value());
  const bool claimed_by_a = a->ClaimNext().has_value();
  if (absl::Now() - before_claim < kLongLease) {
    EXPECT_FALSE(claimed_by_a) << "b's lease holds";
  } else {
    std::cout << "too slow a machine to check that b's lease holds\n";
  }
  b.reset();  // b dies: nobody renews its lease
  std::optional<JobClaims::Claim> again;
  ASSERT_TRUE(WaitUntil([&] { return (again = a->ClaimNext()).has_value(); }, kSafetyNet,
                        absl::Milliseconds(50)));
  EXPECT_EQ(again->id, "orphan");
  EXPECT_EQ(again->attempt, 2);
  EXPECT_GE(absl::Now() - before_claim, kLongLease) << "not before b's lease ran out";
}

TEST_F(PostgresJobClaimsTest, WatchersOnAnotherReplicaSeeEveryChangeLive) {
  std::unique_ptr<PostgresJobStore> a = Replica("a");
  std::unique_ptr<PostgresJobStore> b = Replica("b");
  ASSERT_TRUE(a->Add(NewNotchJob("watched"), "", absl::Now()).ok());
  std::shared_ptr<Job> mirror = b->Find("watched", absl::Now());
  ASSERT_NE(mirror, nullptr);
  auto watcher = std::make_shared<CountingWatcher>(*mirror);
  mirror->AddWatcher(watcher);
  std::shared_ptr<Job> job = ClaimAndRun(*a);
  ASSERT_NE(job, nullptr);
  v1::Progress progress;
  progress.set_iteration(7);
  job->PublishProgress(progress);
  job->FinishWithError(absl::InternalError("ended for the test"), absl::Now());
  ASSERT_TRUE(watcher->ended_.WaitForNotificationWithTimeout(kSafetyNet));
  EXPECT_EQ(mirror->state(), v1::FAILED);
  const v1::Job seen = mirror->ToProto(v1::FULL);
  EXPECT_EQ(seen.event_count(), 3);
  EXPECT_EQ(seen.latest_progress().iteration(), 7);
  EXPECT_EQ(seen.error().message(), "ended for the test");
}

// The issue-24 case: replica a stalls past its lease, b claims the job and is drained (gives it
// back), then a resumes and ends its run. a's end must not be written over the job: the job
// stays queued for a third claim, and a's run is abandoned.
TEST_F(PostgresJobClaimsTest, AReplicaWhoseClaimWasSupersededWritesNothing) {
  std::unique_ptr<PostgresJobStore> a = Replica("a");
  std::unique_ptr<PostgresJobStore> b = Replica("b");
  ASSERT_TRUE(a->Add(NewNotchJob("contested"), "", absl::Now()).ok());
  std::shared_ptr<Job> stale = ClaimAndRun(*a);
  ASSERT_NE(stale, nullptr);
  ASSERT_TRUE(a->Flush(absl::Now() + absl::Seconds(10)));
  EXPECT_EQ(Row("contested"), "2|1|a");

  // a "stalls": its lease is made to expire now, and b claims the job before a renews it.
  JobClaims::Claim b_claim;
  std::shared_ptr<Job> taken_over = TakeOver(*b, &b_claim);
  ASSERT_NE(taken_over, nullptr);
  EXPECT_EQ(b_claim.attempt, 2);
  b->Release(b_claim);  // b is drained before it ends the run
  EXPECT_EQ(Row("contested"), "1|2|");

  // a resumes: its progress and its end reach nothing.
  v1::Progress progress;
  progress.set_iteration(99);
  stale->PublishProgress(progress);
  stale->FinishWithError(absl::CancelledError("interrupted"), absl::Now());
  a->Flush(absl::Now() + absl::Seconds(10));
  EXPECT_EQ(Row("contested"), "1|2|");
  std::shared_ptr<Job> seen = b->Find("contested", absl::Now());
  ASSERT_NE(seen, nullptr);
  EXPECT_EQ(seen->state(), v1::QUEUED);
  EXPECT_NE(seen->ToProto(v1::FULL).latest_progress().iteration(), 99);

  // The next claim runs it to its real end.
  JobClaims::Claim third;
  std::shared_ptr<Job> rerun = ClaimAndRun(*b, &third);
  ASSERT_NE(rerun, nullptr);
  EXPECT_EQ(third.attempt, 3);
  rerun->FinishWithError(absl::InternalError("the real end"), absl::Now());
  ASSERT_TRUE(b->Flush(absl::Now() + absl::Seconds(10)));
  std::shared_ptr<Job> ended = a->Find("contested", absl::Now());
  ASSERT_NE(ended, nullptr);
  EXPECT_EQ(ended->state(), v1::FAILED);
  EXPECT_EQ(ended->ToProto(v1::FULL).error().message(), "the real end");
}

// The lease thread renews only what this replica still runs or has to record: a run whose lease
// another replica holds is abandoned, and ends with that reason, not with its own outcome.
TEST_F(PostgresJobClaimsTest, ARunWhoseLeaseWasTakenIsAbandoned) {
  std::unique_ptr<PostgresJobStore> a = Replica("a");
  std::unique_ptr<PostgresJobStore> b = Replica("b");
  ASSERT_TRUE(a->Add(NewNotchJob("taken"), "", absl::Now()).ok());
  std::shared_ptr<Job> stale = ClaimAndRun(*a);
  ASSERT_NE(stale, nullptr);
  ASSERT_NE(TakeOver(*b), nullptr);
  // a's lease thread notices at its next renewal (every third of the lease).
  const absl::Time until = absl::Now() + absl::Seconds(30);
  while (!stale->interrupter().IsInterrupted() && absl::Now() < until) {
    absl::SleepFor(absl::Milliseconds(20));
  }
  ASSERT_TRUE(stale->interrupter().IsInterrupted());
  v1::QuantizationResult interrupted;
  interrupted.set_termination(v1::INTERRUPTED);
  stale->FinishWithResult(interrupted, absl::Now());
  EXPECT_EQ(stale->state(), v1::FAILED);
  EXPECT_EQ(stale->ToProto(v1::FULL).error().code(),
            static_cast<int32_t>(absl::StatusCode::kUnavailable));
  EXPECT_EQ(Row("taken"), "2|2|b");
}

TEST_F(PostgresJobClaimsTest, ARequestIdNamesOneJobAcrossReplicas) {
  std::unique_ptr<PostgresJobStore> a = Replica("a");
  std::unique_ptr<PostgresJobStore> b = Replica("b");
  ASSERT_TRUE(a->Add(JobWithRequestId("original", "r1", "same"), "", absl::Now()).ok());
  absl::StatusOr<std::shared_ptr<Job>> retry =
      b->Add(JobWithRequestId("duplicate", "r1", "same"), "", absl::Now());
  ASSERT_TRUE(retry.ok()) << retry.status();
  EXPECT_EQ((*retry)->id(), "original");
  EXPECT_EQ(b->Find("duplicate", absl::Now()), nullptr);
  absl::StatusOr<std::shared_ptr<Job>> other =
      b->Add(JobWithRequestId("other", "r1", "different"), "", absl::Now());
  EXPECT_EQ(other.status().code(), absl::StatusCode::kAlreadyExists);
}

TEST_F(PostgresJobClaimsTest, CancellingAQueuedJobOnAnotherReplicaEndsIt) {
  std::unique_ptr<PostgresJobStore> a = Replica("a");
  std::unique_ptr<PostgresJobStore> b = Replica("b");
  ASSERT_TRUE(a->Add(NewNotchJob("doomed"), "", absl::Now()).ok());
  std::shared_ptr<Job> mirror = b->Find("doomed", absl::Now());
  ASSERT_NE(mirror, nullptr);
  b->Cancel(*mirror, absl::Now());
  EXPECT_EQ(mirror->state(), v1::CANCELLED);
  EXPECT_EQ(a->Find("doomed", absl::Now())->state(), v1::CANCELLED);
  EXPECT_FALSE(a->ClaimNext().has_value());
}

// The query of KEDA's postgresql trigger in deploy/kubernetes/components/keda/scaled-object.yaml
// (the line `query: "..."`), read from the source tree.
std::string KedaQueueQuery() {
  std::ifstream file(ISPQ_KEDA_SCALED_OBJECT);
  const std::string text((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  const std::string key = "query: \"";
  const size_t start = text.find(key);
  if (start == std::string::npos) return "no query in " ISPQ_KEDA_SCALED_OBJECT;
  const size_t end = text.find('"', start + key.size());
  return text.substr(start + key.size(), end - start - key.size());
}

// KEDA scales the replicas on that query: on a real database with jobs in every state, it counts
// exactly the queued jobs any replica may claim, as QueuedCount (ispq_queue_length) does. Not a
// running job, one whose lease expired (claimable, but running), an ended one, nor the queued job
// of a Quantize call (it runs on the replica that took the call, whatever the replica count).
TEST_F(PostgresJobClaimsTest, KedasQueryCountsExactlyTheQueuedJobs) {
  const std::string query = KedaQueueQuery();
  ASSERT_EQ(query.rfind("SELECT count(*) FROM ispq_jobs", 0), 0u) << query;
  std::unique_ptr<PostgresJobStore> a = Replica("a");
  auto count = [&]() -> std::string {
    absl::StatusOr<std::string> rows = postgres_->Sql(query, Database());
    return rows.ok() ? std::string(absl::StripAsciiWhitespace(*rows)) : rows.status().ToString();
  };
  EXPECT_EQ(count(), "0");
  for (const char* id : {"running", "expired", "ended", "queued1", "queued2"}) {
    ASSERT_TRUE(a->Add(NewNotchJob(id), "", absl::Now()).ok()) << id;
  }
  ASSERT_TRUE(
      a->Add(std::make_shared<Job>("call", NotchJobSpec(), /*bound_to_call=*/true, 0, absl::Now()),
             "", absl::Now())
          .ok());
  EXPECT_EQ(count(), "5");
  ASSERT_NE(ClaimAndRun(*a), nullptr);  // "running"
  ASSERT_NE(ClaimAndRun(*a), nullptr);  // "expired", after its lease is made to expire below
  ASSERT_TRUE(postgres_
                  ->Sql("UPDATE ispq_jobs SET lease_expires = now() - interval '1 hour' WHERE "
                        "id = 'expired'",
                        Database())
                  .ok());
  std::shared_ptr<Job> ended = a->Find("ended", absl::Now());
  ASSERT_NE(ended, nullptr);
  a->Cancel(*ended, absl::Now());
  ASSERT_EQ(Row("ended").substr(0, 1), std::to_string(static_cast<int>(v1::CANCELLED)));
  EXPECT_EQ(count(), "2") << "queued1 and queued2";
  EXPECT_EQ(count(), std::to_string(a->QueuedCount()));
}

TEST_F(PostgresJobClaimsTest, RefusesAUriThatIsNotPostgres) {
  PostgresJobStoreOptions options;
  options.uri = "mysql://localhost/x";
  absl::StatusOr<std::unique_ptr<PostgresJobStore>> store = PostgresJobStore::Open(options);
  EXPECT_EQ(store.status().code(), absl::StatusCode::kInvalidArgument);
  options.uri = "postgresql://nobody@127.0.0.1:1/none?connect_timeout=2";
  absl::StatusOr<std::unique_ptr<PostgresJobStore>> unreachable = PostgresJobStore::Open(options);
  EXPECT_EQ(unreachable.status().code(), absl::StatusCode::kUnavailable);
}

}  // namespace
}  // namespace ispq::server

namespace ispq::server {
namespace {

TEST_F(PostgresJobClaimsTest, CancellingARunningJobOnAnotherReplicaInterruptsItsRun) {
  std::unique_ptr<PostgresJobStore> a = Replica("a");
  std::unique_ptr<PostgresJobStore> b = Replica("b");
  ASSERT_TRUE(a->Add(NewNotchJob("running"), "", absl::Now()).ok());
  std::shared_ptr<Job> runner = ClaimAndRun(*a);
  ASSERT_NE(runner, nullptr);
  std::shared_ptr<Job> mirror = b->Find("running", absl::Now());
  ASSERT_NE(mirror, nullptr);
  EXPECT_EQ(mirror->state(), v1::RUNNING);
  b->Cancel(*mirror, absl::Now());
  EXPECT_TRUE(WaitUntil([&] { return runner->interrupter().IsInterrupted(); }));
}

}  // namespace
}  // namespace ispq::server
