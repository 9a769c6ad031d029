// SPDX-License-Identifier: Apache-2.0
// PostgresJobRecorder (server/store/postgres/postgres_job_recorder.h) on a real PostgreSQL: the
// runs it records reach their rows, every write is fenced by the lease (a replica that lost it
// writes nothing and abandons its run), draining gives runs back, and a write that fails is
// retried until it lands.
#include "server/store/postgres/postgres_job_recorder.h"

#include <algorithm>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "absl/strings/ascii.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "gtest/gtest.h"
#include "server/store/postgres/postgres_connections.h"
#include "server/store/postgres/postgres_job_rows.h"
#include "server/store/postgres/postgres_schema.h"
#include "tests/server/server_test_jobs.h"
#include "tests/support/bounded_wait.h"
#include "tests/support/postgres_suite.h"

namespace ispq::server {
namespace {

using ::ispq::testing::kSafetyNet;

const absl::Time kT0 = absl::FromUnixSeconds(1'000'000);
constexpr char kReplica[] = "here";

class PostgresJobRecorderTest : public ispq::testing::PostgresSuite {
 protected:
  void SetUp() override {
    database_ = absl::StrCat("recorder", next_database_++);
    absl::StatusOr<std::string> uri = postgres_->CreateDatabase(database_);
    ASSERT_TRUE(uri.ok()) << uri.status();
    absl::StatusOr<std::shared_ptr<PostgresConnections>> connections =
        PostgresConnections::Connect({.uri = *uri, .size = 2});
    ASSERT_TRUE(connections.ok()) << connections.status();
    connections_ = *connections;
    ASSERT_TRUE(MigratePostgresSchema(*connections_).ok());
    recorder_ = std::make_shared<PostgresJobRecorder>(connections_, kReplica, RetentionPolicy());
  }
  void TearDown() override {
    if (recorder_ != nullptr) recorder_->Stop();
  }

  struct Row {
    std::string id;
    v1::JobState state = v1::RUNNING;
    std::string lease_owner = kReplica;
    int attempts = 1;
    bool bound_to_call = false;
    bool cancel_requested = false;
    std::optional<absl::Time> end = std::nullopt;
  };
  // The row of a job as a claim (or, bound to a call, its creation) left it, after its accepted
  // event.
  void Insert(const Row& row) {
    v1::Job summary;
    summary.set_name(absl::StrCat("jobs/", row.id));
    summary.set_state(row.state);
    summary.set_event_count(1);
    const absl::Status status = connections_->Run([&](pqxx::connection& connection) {
      pqxx::work work(connection);
      work.exec_params(
          "INSERT INTO ispq_jobs (id, owner, bound_to_call, state, summary, request, "
          "create_time_ns, end_time_ns, next_sequence, cancel_requested, lease_owner, "
          "lease_expires, attempts) VALUES ($1, 'o', $2, $3, $4, 'request', $5, "
          "NULLIF($6::bigint, -1), 1, $7, $8, now() + interval '1 hour', $9)",
          row.id, row.bound_to_call, static_cast<int>(row.state), ProtoBytes(summary),
          absl::ToUnixNanos(kT0), row.end.has_value() ? absl::ToUnixNanos(*row.end) : int64_t{-1},
          row.cancel_requested, row.lease_owner, row.attempts);
      work.commit();
    });
    ASSERT_TRUE(status.ok()) << status;
  }

  // A run of the stored job `id` here under `attempt`, recorded by `recorder_`, as
  // PostgresJobStore::Adopt sets it up.
  std::shared_ptr<Job> Run(const std::string& id, int attempt) {
    std::shared_ptr<Job> run = Job::Resume(id, NotchJobSpec(), /*bound_to_call=*/false, kT0,
                                           /*next_sequence=*/1, nullptr);
    recorder_->Track(run, attempt);
    run->SetEventSink(recorder_);
    return run;
  }

  bool Flush() { return recorder_->Flush(absl::Now() + kSafetyNet); }

  // The row as `state|attempts|lease owner|ended|has request`.
  std::string RowOf(const std::string& id) {
    return Sql(absl::StrCat(
        "SELECT state || '|' || attempts || '|' || coalesce(lease_owner, '') || '|' || "
        "(end_time_ns IS NOT NULL) || '|' || (request IS NOT NULL) FROM ispq_jobs WHERE id = '",
        id, "'"));
  }
  // The stored events of `id` as `kind@sequence`, in order.
  std::string Events(const std::string& id) {
    return Sql(
        absl::StrCat("SELECT string_agg(kind || '@' || sequence, ',' ORDER BY sequence) "
                     "FROM ispq_job_events WHERE job_id = '",
                     id, "'"));
  }
  std::optional<StoredJob> Load(const std::string& id) {
    std::optional<StoredJob> stored;
    EXPECT_TRUE(connections_
                    ->Run([&](pqxx::connection& connection) {
                      pqxx::work work(connection);
                      stored = LoadStoredJob(work, id, absl::InfinitePast());
                    })
                    .ok());
    return stored;
  }
  std::string Leases() {
    std::vector<std::string> leases;
    for (const JobLease& lease : recorder_->Leases()) {
      leases.push_back(absl::StrCat(lease.id, "@", lease.attempt));
    }
    std::sort(leases.begin(), leases.end());
    return absl::StrJoin(leases, ",");
  }
  std::string Sql(const std::string& sql) {
    absl::StatusOr<std::string> output = postgres_->Sql(sql, database_);
    return output.ok() ? std::string(absl::StripAsciiWhitespace(*output))
                       : output.status().ToString();
  }

  static v1::Progress Iteration(int iteration) {
    v1::Progress progress;
    progress.set_iteration(iteration);
    return progress;
  }
  static v1::QuantizationResult Interrupted() {
    v1::QuantizationResult result;
    result.set_termination(v1::INTERRUPTED);
    return result;
  }

  std::string database_;
  std::shared_ptr<PostgresConnections> connections_;
  std::shared_ptr<PostgresJobRecorder> recorder_;
};

TEST_F(PostgresJobRecorderTest, RecordsARunUnderItsLeaseAndLetsGoOfTheLeaseAtTheEnd) {
  Insert({.id = "j", .state = v1::QUEUED});
  std::shared_ptr<Job> run = Run("j", 1);
  EXPECT_EQ(Leases(), "j@1");
  ASSERT_TRUE(run->Start(kT0));
  ASSERT_TRUE(Flush());
  EXPECT_EQ(RowOf("j"), "2|1|here|false|true");
  run->PublishProgress(Iteration(4));
  ASSERT_TRUE(Flush());
  std::optional<StoredJob> stored = Load("j");
  ASSERT_TRUE(stored.has_value());
  EXPECT_EQ(stored->summary.latest_progress().iteration(), 4);
  EXPECT_EQ(Events("j"), "1@1");
  EXPECT_EQ(Leases(), "j@1") << "renewed while it runs";

  run->FinishWithError(absl::InternalError("broke"), kT0 + absl::Seconds(1));
  ASSERT_TRUE(Flush());
  EXPECT_EQ(RowOf("j"), "4|1||true|false") << "ended: no lease, no request";
  EXPECT_EQ(Events("j"), "1@1,3@2");
  stored = Load("j");
  ASSERT_TRUE(stored.has_value());
  EXPECT_EQ(stored->summary.event_count(), 3);
  EXPECT_EQ(stored->events.back().error().message(), "broke");
  EXPECT_EQ(Leases(), "") << "nothing left to renew once the end is written";
}

// The fence: a write needs this replica's name, the claim's attempt and a live row. A run that
// finds any of them changed writes nothing and is abandoned: its outcome did not happen.
TEST_F(PostgresJobRecorderTest, ARunThatLostItsLeaseWritesNothingAndIsAbandoned) {
  Insert({.id = "taken", .lease_owner = "elsewhere", .attempts = 2});
  Insert({.id = "reclaimed", .attempts = 3});  // this replica's own later claim
  Insert({.id = "ended", .state = v1::FAILED, .end = kT0});
  std::vector<std::shared_ptr<Job>> runs = {Run("taken", 1), Run("reclaimed", 2), Run("ended", 1)};
  for (const std::shared_ptr<Job>& run : runs) {
    ASSERT_TRUE(run->Start(kT0));
    run->PublishProgress(Iteration(9));
  }
  ASSERT_TRUE(Flush());
  EXPECT_EQ(RowOf("taken"), "2|2|elsewhere|false|true");
  EXPECT_EQ(RowOf("reclaimed"), "2|3|here|false|true");
  EXPECT_EQ(RowOf("ended"), "4|1|here|true|true");
  EXPECT_EQ(Sql("SELECT count(*) FROM ispq_job_events"), "0");
  EXPECT_EQ(Leases(), "");
  for (const std::shared_ptr<Job>& run : runs) {
    EXPECT_TRUE(run->interrupter().IsInterrupted()) << run->id();
    run->FinishWithResult(Interrupted(), kT0 + absl::Seconds(1));
    EXPECT_EQ(run->state(), v1::FAILED) << run->id();
    EXPECT_EQ(run->ToProto(v1::BASIC).error().code(),
              static_cast<int32_t>(absl::StatusCode::kUnavailable));
  }
  ASSERT_TRUE(Flush());
  EXPECT_EQ(RowOf("taken"), "2|2|elsewhere|false|true") << "nor is the end written";
}

// What the store's lease thread reports: only the attempt it names is lost.
TEST_F(PostgresJobRecorderTest, ALostLeaseAbandonsTheRunOfThatAttemptOnly) {
  Insert({.id = "j"});
  std::shared_ptr<Job> run = Run("j", 1);
  ASSERT_TRUE(run->Start(kT0));
  recorder_->LeaseLost({.id = "j", .attempt = 0});
  recorder_->LeaseLost({.id = "other", .attempt = 1});
  EXPECT_FALSE(run->interrupter().IsInterrupted());
  EXPECT_EQ(Leases(), "j@1");
  recorder_->LeaseLost({.id = "j", .attempt = 1});
  EXPECT_TRUE(run->interrupter().IsInterrupted());
  EXPECT_EQ(Leases(), "");
  run->PublishProgress(Iteration(3));
  ASSERT_TRUE(Flush());
  EXPECT_EQ(Events("j"), "") << "its records were dropped";
}

// This replica claimed the job again after its earlier lease expired while it stalled: the
// earlier run stops, and only the new one is recorded.
TEST_F(PostgresJobRecorderTest, TrackingANewerClaimAbandonsTheEarlierRun) {
  Insert({.id = "j", .attempts = 2});
  std::shared_ptr<Job> earlier = Run("j", 1);
  ASSERT_TRUE(earlier->Start(kT0));
  std::shared_ptr<Job> later = Run("j", 2);
  EXPECT_TRUE(earlier->interrupter().IsInterrupted());
  EXPECT_FALSE(later->interrupter().IsInterrupted());
  EXPECT_EQ(Leases(), "j@2");
  ASSERT_TRUE(later->Start(kT0));
  later->PublishProgress(Iteration(2));
  earlier->PublishProgress(Iteration(1));  // after the later run's: must not win
  ASSERT_TRUE(Flush());
  std::optional<StoredJob> stored = Load("j");
  ASSERT_TRUE(stored.has_value());
  EXPECT_EQ(stored->summary.latest_progress().iteration(), 2);
  EXPECT_EQ(stored->events.size(), 1u);
}

// Shutdown: a run interrupted by the drain goes back to the queue for another replica, with its
// request, instead of ending with a partial result.
TEST_F(PostgresJobRecorderTest, DrainingGivesAnInterruptedRunBackToTheQueue) {
  Insert({.id = "j"});
  std::shared_ptr<Job> run = Run("j", 1);
  ASSERT_TRUE(run->Start(kT0));
  ASSERT_TRUE(Flush());
  recorder_->BeginDraining();
  run->FinishWithResult(Interrupted(), kT0 + absl::Seconds(1));
  ASSERT_TRUE(Flush());
  EXPECT_EQ(RowOf("j"), "1|1||false|true");
  EXPECT_EQ(Events("j"), "") << "no end was written";
  EXPECT_EQ(Leases(), "");
}

TEST_F(PostgresJobRecorderTest, DrainingEndsACancelledRunInsteadOfGivingItBack) {
  Insert({.id = "j", .cancel_requested = true});
  std::shared_ptr<Job> run = Run("j", 1);
  ASSERT_TRUE(run->Start(kT0));
  run->RequestCancel();  // as the store does when it hears of the cancellation
  recorder_->BeginDraining();
  run->FinishWithResult(Interrupted(), kT0 + absl::Seconds(1));
  ASSERT_EQ(run->state(), v1::CANCELLED);
  ASSERT_TRUE(Flush());
  EXPECT_EQ(RowOf("j"), "5|1||true|false");
  EXPECT_EQ(Events("j"), "3@1");
}

// A call-bound job's call ends with the replica: there is nobody to give it back to.
TEST_F(PostgresJobRecorderTest, DrainingEndsACallBoundRun) {
  Insert({.id = "call", .state = v1::QUEUED, .attempts = 0, .bound_to_call = true});
  auto run = std::make_shared<Job>("call", NotchJobSpec(), /*bound_to_call=*/true, 0, kT0);
  recorder_->Track(run, 0);
  run->SetEventSink(recorder_);
  ASSERT_TRUE(run->Start(kT0));
  recorder_->BeginDraining();
  run->FinishWithResult(Interrupted(), kT0 + absl::Seconds(1));
  ASSERT_TRUE(Flush());
  EXPECT_EQ(RowOf("call"), absl::StrCat(static_cast<int>(run->state()), "|0||true|false"));
}

// The database fails the write (here: the table is gone for a while): the record is kept and
// retried until it lands; the run is not abandoned for it.
TEST_F(PostgresJobRecorderTest, AFailedWriteIsRetriedUntilItLands) {
  Insert({.id = "j"});
  std::shared_ptr<Job> run = Run("j", 1);
  ASSERT_TRUE(run->Start(kT0));
  ASSERT_TRUE(Flush());
  ASSERT_EQ(Sql("ALTER TABLE ispq_jobs RENAME TO ispq_jobs_away"), "");
  run->PublishProgress(Iteration(5));
  EXPECT_FALSE(recorder_->Flush(absl::Now() + absl::Milliseconds(300)));
  EXPECT_FALSE(run->interrupter().IsInterrupted());
  EXPECT_EQ(Leases(), "j@1");
  ASSERT_EQ(Sql("ALTER TABLE ispq_jobs_away RENAME TO ispq_jobs"), "");
  ASSERT_TRUE(Flush());
  std::optional<StoredJob> stored = Load("j");
  ASSERT_TRUE(stored.has_value());
  EXPECT_EQ(stored->summary.latest_progress().iteration(), 5);
}

TEST_F(PostgresJobRecorderTest, WritingAnEndPrunesFinishedJobsBeyondTheRetention) {
  recorder_->Stop();
  recorder_ = std::make_shared<PostgresJobRecorder>(
      connections_, kReplica, RetentionPolicy{.max_finished = 1, .max_age = absl::Hours(1)});
  Insert({.id = "older", .state = v1::FAILED, .end = kT0});
  Insert({.id = "j"});
  std::shared_ptr<Job> run = Run("j", 1);
  ASSERT_TRUE(run->Start(kT0));
  run->FinishWithError(absl::InternalError("broke"), kT0 + absl::Seconds(1));
  ASSERT_TRUE(Flush());
  EXPECT_EQ(Sql("SELECT string_agg(id, ',') FROM ispq_jobs"), "j");
}

TEST_F(PostgresJobRecorderTest, AfterStopNothingMoreIsWritten) {
  Insert({.id = "j"});
  std::shared_ptr<Job> run = Run("j", 1);
  recorder_->Stop();
  EXPECT_EQ(Leases(), "");
  ASSERT_TRUE(run->Start(kT0));
  run->FinishWithError(absl::InternalError("broke"), kT0);
  EXPECT_TRUE(Flush());
  EXPECT_EQ(RowOf("j"), "2|1|here|false|true");
}

}  // namespace
}  // namespace ispq::server
