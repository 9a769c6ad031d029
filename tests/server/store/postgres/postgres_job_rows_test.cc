// SPDX-License-Identifier: Apache-2.0
// The rows of one job in the PostgreSQL job store (server/store/postgres/postgres_job_rows.h) on
// a real PostgreSQL: what is written reads back the same, one event is kept per kind, ending a
// job that no replica runs, notifications, and pruning by the retention policy.
#include "server/store/postgres/postgres_job_rows.h"

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "absl/strings/ascii.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "google/protobuf/util/message_differencer.h"
#include "google/protobuf/util/time_util.h"
#include "gtest/gtest.h"
#include "server/store/postgres/postgres_connections.h"
#include "server/store/postgres/postgres_schema.h"
#include "tests/server/server_test_jobs.h"
#include "tests/support/bounded_wait.h"
#include "tests/support/postgres_suite.h"

namespace ispq::server {
namespace {

using ::google::protobuf::util::MessageDifferencer;
using ::google::protobuf::util::TimeUtil;

const absl::Time kT0 = absl::FromUnixSeconds(1'000'000);

v1::QuantizeEvent Event(int64_t sequence) {
  v1::QuantizeEvent event;
  event.set_job("jobs/j");
  event.set_sequence(sequence);
  *event.mutable_time() = TimeUtil::NanosecondsToTimestamp(absl::ToUnixNanos(kT0) + sequence);
  return event;
}
v1::QuantizeEvent Accepted(int64_t sequence) {
  v1::QuantizeEvent event = Event(sequence);
  event.mutable_accepted()->set_mesh_display_name("notch");
  event.mutable_accepted()->set_scaling(0.5);  // a double: zero bytes in the encoding
  return event;
}
v1::QuantizeEvent Progress(int64_t sequence, int iteration) {
  v1::QuantizeEvent event = Event(sequence);
  event.mutable_progress()->set_iteration(iteration);
  return event;
}
v1::QuantizeEvent Intermediate(int64_t sequence) {
  v1::QuantizeEvent event = Event(sequence);
  event.mutable_intermediate()->mutable_progress()->set_iteration(1);
  return event;
}
v1::QuantizeEvent Failed(int64_t sequence, const std::string& message) {
  v1::QuantizeEvent event = Event(sequence);
  event.mutable_error()->set_code(static_cast<int32_t>(absl::StatusCode::kInternal));
  event.mutable_error()->set_message(message);
  return event;
}

// The kinds of `events`, in order, as a string such as "progress,error".
std::string Kinds(const std::vector<v1::QuantizeEvent>& events) {
  std::string kinds;
  for (const v1::QuantizeEvent& event : events) {
    absl::StrAppend(&kinds, kinds.empty() ? "" : ",",
                    v1::QuantizeEvent::descriptor()->FindFieldByNumber(event.kind_case())->name());
  }
  return kinds;
}

TEST(PostgresJobRowsEncodingTest, EachEventKindHasItsStoredKind) {
  EXPECT_EQ(EventKind(Accepted(0)), StoredEventKind::kAccepted);
  EXPECT_EQ(EventKind(Progress(1, 1)), StoredEventKind::kProgress);
  EXPECT_EQ(EventKind(Intermediate(2)), StoredEventKind::kIntermediate);
  EXPECT_EQ(EventKind(Failed(3, "x")), StoredEventKind::kTerminal);
  v1::QuantizeEvent result = Event(3);
  result.mutable_result()->set_objective(1.5);
  EXPECT_EQ(EventKind(result), StoredEventKind::kTerminal);
}

TEST(PostgresJobRowsEncodingTest, OnlySucceededFailedAndCancelledAreTerminal) {
  EXPECT_FALSE(IsTerminal(v1::JOB_STATE_UNSPECIFIED));
  EXPECT_FALSE(IsTerminal(v1::QUEUED));
  EXPECT_FALSE(IsTerminal(v1::RUNNING));
  EXPECT_TRUE(IsTerminal(v1::SUCCEEDED));
  EXPECT_TRUE(IsTerminal(v1::FAILED));
  EXPECT_TRUE(IsTerminal(v1::CANCELLED));
}

// The row keeps the summary without the outcome: the terminal event holds it, once.
TEST(PostgresJobRowsEncodingTest, TheRowSummaryLeavesTheOutcomeToTheTerminalEvent) {
  std::shared_ptr<Job> failed = NewNotchJob("failed", kT0);
  failed->FinishWithError(absl::InternalError("broke"), kT0 + absl::Seconds(1));
  ASSERT_TRUE(failed->ToProto(v1::BASIC).has_error());
  const v1::Job summary = RowSummary(*failed);
  EXPECT_FALSE(summary.has_error());
  EXPECT_EQ(summary.state(), v1::FAILED);
  EXPECT_TRUE(summary.done());
  EXPECT_EQ(summary.event_count(), 2);
  EXPECT_EQ(summary.name(), "jobs/failed");

  std::shared_ptr<Job> succeeded = NewNotchJob("succeeded", kT0);
  ASSERT_TRUE(succeeded->Start(kT0));
  v1::QuantizationResult result;
  result.set_objective(2.25);
  result.set_termination(v1::OPTIMAL);
  succeeded->FinishWithResult(result, kT0 + absl::Seconds(1));
  ASSERT_TRUE(succeeded->ToProto(v1::BASIC).has_result());
  EXPECT_FALSE(RowSummary(*succeeded).has_result());
  EXPECT_EQ(RowSummary(*succeeded).state(), v1::SUCCEEDED);
}

class PostgresJobRowsTest : public ispq::testing::PostgresSuite {
 protected:
  void SetUp() override {
    database_ = absl::StrCat("rows", next_database_++);
    absl::StatusOr<std::string> uri = postgres_->CreateDatabase(database_);
    ASSERT_TRUE(uri.ok()) << uri.status();
    absl::StatusOr<std::shared_ptr<PostgresConnections>> connections =
        PostgresConnections::Connect({.uri = *uri, .size = 2});
    ASSERT_TRUE(connections.ok()) << connections.status();
    connections_ = *connections;
    ASSERT_TRUE(MigratePostgresSchema(*connections_).ok());
  }

  // Runs `body` in one committed transaction.
  void Transaction(const std::function<void(pqxx::work&)>& body) {
    const absl::Status status = connections_->Run([&](pqxx::connection& connection) {
      pqxx::work work(connection);
      body(work);
      work.commit();
    });
    ASSERT_TRUE(status.ok()) << status;
  }

  struct Row {
    std::string id;
    v1::JobState state = v1::QUEUED;
    int64_t next_sequence = 1;
    std::optional<absl::Time> end = std::nullopt;
    std::string lease_owner = "";  // empty: none
    bool cancel_requested = false;
  };
  // A job row as the store writes it, with `row.state` in the row and QUEUED in the summary.
  void Insert(const Row& row) {
    v1::Job summary;
    summary.set_name(absl::StrCat("jobs/", row.id));
    summary.set_state(v1::QUEUED);
    summary.set_scaling(0.5);
    summary.set_event_count(row.next_sequence);
    Transaction([&](pqxx::work& work) {
      work.exec_params(
          "INSERT INTO ispq_jobs (id, owner, bound_to_call, state, summary, request, "
          "create_time_ns, end_time_ns, next_sequence, cancel_requested, lease_owner, "
          "lease_expires) VALUES ($1, 'o', false, $2, $3, 'request', $4, NULLIF($5::bigint, -1), "
          "$6, "
          "$7, NULLIF($8, ''), CASE WHEN $8 = '' THEN NULL ELSE now() END)",
          row.id, static_cast<int>(row.state), ProtoBytes(summary), absl::ToUnixNanos(kT0),
          row.end.has_value() ? absl::ToUnixNanos(*row.end) : int64_t{-1}, row.next_sequence,
          row.cancel_requested, row.lease_owner);
    });
  }

  std::optional<StoredJob> Load(const std::string& id, absl::Time retained_since = kT0,
                                bool terminal_only = false) {
    std::optional<StoredJob> stored;
    Transaction(
        [&](pqxx::work& work) { stored = LoadStoredJob(work, id, retained_since, terminal_only); });
    return stored;
  }

  // One SQL command's output in the test's database, trimmed.
  std::string Sql(const std::string& sql) {
    absl::StatusOr<std::string> output = postgres_->Sql(sql, database_);
    return output.ok() ? std::string(absl::StripAsciiWhitespace(*output))
                       : output.status().ToString();
  }
  std::string Ids() { return Sql("SELECT string_agg(id, ',' ORDER BY id) FROM ispq_jobs"); }

  std::string database_;
  std::shared_ptr<PostgresConnections> connections_;
};

TEST_F(PostgresJobRowsTest, EventsReadBackAsWrittenInSequenceOrder) {
  Insert({.id = "j", .state = v1::RUNNING, .next_sequence = 6});
  const std::vector<v1::QuantizeEvent> written = {Progress(5, 9), Accepted(0), Intermediate(3)};
  Transaction([&](pqxx::work& work) {
    for (const v1::QuantizeEvent& event : written) StoreEvent(work, "j", event);
  });
  std::optional<StoredJob> stored = Load("j");
  ASSERT_TRUE(stored.has_value());
  ASSERT_EQ(stored->events.size(), 3u);
  EXPECT_TRUE(MessageDifferencer::Equals(stored->events[0], written[1]));
  EXPECT_TRUE(MessageDifferencer::Equals(stored->events[1], written[2]));
  EXPECT_TRUE(MessageDifferencer::Equals(stored->events[2], written[0]));
  EXPECT_EQ(stored->summary.name(), "jobs/j");
  EXPECT_EQ(stored->summary.scaling(), 0.5);
  EXPECT_EQ(stored->summary.event_count(), 6);
}

// The row's state column is the truth (claims and sweeps change it without the summary).
TEST_F(PostgresJobRowsTest, StateDoneAndCancellationComeFromTheRow) {
  Insert({.id = "running", .state = v1::RUNNING, .cancel_requested = true});
  Insert({.id = "ended", .state = v1::CANCELLED, .end = kT0});
  std::optional<StoredJob> running = Load("running");
  ASSERT_TRUE(running.has_value());
  EXPECT_EQ(running->summary.state(), v1::RUNNING);
  EXPECT_FALSE(running->summary.done());
  EXPECT_TRUE(running->cancel_requested);
  std::optional<StoredJob> ended = Load("ended");
  ASSERT_TRUE(ended.has_value());
  EXPECT_EQ(ended->summary.state(), v1::CANCELLED);
  EXPECT_TRUE(ended->summary.done());
  EXPECT_FALSE(ended->cancel_requested);
}

TEST_F(PostgresJobRowsTest, JobsThatEndedBeforeTheRetainedTimeAreNotLoaded) {
  Insert({.id = "old", .state = v1::FAILED, .end = kT0 - absl::Nanoseconds(1)});
  Insert({.id = "just", .state = v1::FAILED, .end = kT0});
  Insert({.id = "live", .state = v1::QUEUED});
  EXPECT_FALSE(Load("old", kT0).has_value());
  EXPECT_TRUE(Load("old", kT0 - absl::Seconds(1)).has_value());
  EXPECT_TRUE(Load("just", kT0).has_value());
  EXPECT_TRUE(Load("live", absl::InfiniteFuture()).has_value()) << "a live job is always kept";
  EXPECT_FALSE(Load("unknown", absl::InfinitePast()).has_value());
}

// One kept event per kind (server/model/job_event_log.h's bound), and no intermediate q once
// the job has ended.
TEST_F(PostgresJobRowsTest, KeepsTheLatestEventOfEachKindAndDropsTheIntermediateAtTheEnd) {
  Insert({.id = "j", .state = v1::RUNNING, .next_sequence = 1});
  Transaction([&](pqxx::work& work) {
    StoreEvent(work, "j", Accepted(0));
    StoreEvent(work, "j", Progress(1, 1));
    StoreEvent(work, "j", Intermediate(2));
    StoreEvent(work, "j", Progress(3, 2));
  });
  std::optional<StoredJob> stored = Load("j");
  ASSERT_TRUE(stored.has_value());
  EXPECT_EQ(Kinds(stored->events), "accepted,intermediate,progress");
  EXPECT_EQ(stored->events.back().progress().iteration(), 2);
  EXPECT_EQ(stored->events.back().sequence(), 3);

  Transaction([&](pqxx::work& work) { StoreEvent(work, "j", Failed(4, "broke")); });
  stored = Load("j");
  ASSERT_TRUE(stored.has_value());
  EXPECT_EQ(Kinds(stored->events), "accepted,progress,error");
  std::optional<StoredJob> terminal = Load("j", kT0, /*terminal_only=*/true);
  ASSERT_TRUE(terminal.has_value());
  EXPECT_EQ(Kinds(terminal->events), "error");
}

// A job that no replica runs ends in the database alone: a terminal event numbered after the
// events seen so far, the row ended and let go of its request and lease.
TEST_F(PostgresJobRowsTest, EndingAStoredJobWritesItsTerminalEventAndReleasesIt) {
  Insert({.id = "cancelled", .state = v1::QUEUED, .next_sequence = 3, .lease_owner = "a"});
  Insert({.id = "failed", .state = v1::RUNNING, .next_sequence = 1});
  const absl::Time now = kT0 + absl::Seconds(7);
  Transaction([&](pqxx::work& work) {
    EndStoredJob(work, "cancelled", absl::CancelledError("cancelled while queued"), now);
    EndStoredJob(work, "failed", absl::UnavailableError("its replica died"), now);
  });
  EXPECT_EQ(Sql("SELECT state || '|' || next_sequence || '|' || end_time_ns || '|' || "
                "(request IS NULL) || '|' || (lease_owner IS NULL) || '|' || "
                "(lease_expires IS NULL) FROM ispq_jobs WHERE id = 'cancelled'"),
            absl::StrCat(static_cast<int>(v1::CANCELLED), "|4|", absl::ToUnixNanos(now),
                         "|true|true|true"));
  std::optional<StoredJob> cancelled = Load("cancelled");
  ASSERT_TRUE(cancelled.has_value());
  EXPECT_EQ(cancelled->summary.state(), v1::CANCELLED);
  EXPECT_EQ(cancelled->summary.event_count(), 4);
  EXPECT_EQ(TimeUtil::TimestampToNanoseconds(cancelled->summary.end_time()),
            absl::ToUnixNanos(now));
  ASSERT_EQ(cancelled->events.size(), 1u);
  const v1::QuantizeEvent& end = cancelled->events[0];
  EXPECT_EQ(end.job(), "jobs/cancelled");
  EXPECT_EQ(end.sequence(), 3);
  EXPECT_EQ(end.error().code(), static_cast<int32_t>(absl::StatusCode::kCancelled));
  EXPECT_EQ(end.error().message(), "cancelled while queued");

  std::optional<StoredJob> failed = Load("failed");
  ASSERT_TRUE(failed.has_value());
  EXPECT_EQ(failed->summary.state(), v1::FAILED);
  ASSERT_EQ(failed->events.size(), 1u);
  EXPECT_EQ(failed->events[0].error().code(), static_cast<int32_t>(absl::StatusCode::kUnavailable));
}

TEST_F(PostgresJobRowsTest, EndingAnEndedJobChangesNothing) {
  Insert({.id = "j", .state = v1::RUNNING, .next_sequence = 2});
  Transaction([&](pqxx::work& work) {
    EndStoredJob(work, "j", absl::InternalError("first"), kT0 + absl::Seconds(1));
  });
  Transaction([&](pqxx::work& work) {
    EndStoredJob(work, "j", absl::CancelledError("second"), kT0 + absl::Seconds(2));
    EndStoredJob(work, "unknown", absl::CancelledError("nobody"), kT0);
  });
  std::optional<StoredJob> stored = Load("j");
  ASSERT_TRUE(stored.has_value());
  EXPECT_EQ(stored->summary.state(), v1::FAILED);
  EXPECT_EQ(stored->summary.event_count(), 3);
  ASSERT_EQ(stored->events.size(), 1u);
  EXPECT_EQ(stored->events[0].error().message(), "first");
  EXPECT_EQ(Ids(), "j");
}

// What every replica's listener hears: the changed job's id, or that a job may be claimable;
// nothing from a transaction that did not commit.
TEST_F(PostgresJobRowsTest, NotifiesTheChangedJobAndTheQueueOnCommit) {
  pqxx::connection listening(postgres_->uri(database_));
  std::vector<std::string> heard;
  class Receiver final : public pqxx::notification_receiver {
   public:
    Receiver(pqxx::connection& connection, const std::string& channel,
             std::vector<std::string>& heard)
        : pqxx::notification_receiver(connection, channel), heard_(heard) {}
    void operator()(const std::string& payload, int /*backend_pid*/) override {
      heard_.push_back(absl::StrCat(channel(), ":", payload));
    }

   private:
    std::vector<std::string>& heard_;
  };
  Receiver changed(listening, kJobChangedChannel, heard);
  Receiver queued(listening, kJobQueuedChannel, heard);
  listening.get_notifs();  // LISTEN takes effect

  ASSERT_TRUE(connections_
                  ->Run([](pqxx::connection& connection) {
                    pqxx::work work(connection);
                    NotifyJobChanged(work, "rolled-back");
                  })
                  .ok());
  Transaction([](pqxx::work& work) {
    NotifyJobChanged(work, "j1");
    NotifyJobQueued(work);
  });
  Transaction([](pqxx::work& work) { NotifyJobChanged(work, "j2"); });
  const absl::Time deadline = absl::Now() + ispq::testing::kSafetyNet;
  while (heard.size() < 3 && absl::Now() < deadline) listening.await_notification(1, 0);
  EXPECT_EQ(absl::StrJoin(heard, " "), "ispq_job_changed:j1 ispq_job_queued: ispq_job_changed:j2");
}

TEST_F(PostgresJobRowsTest, PruningDropsFinishedJobsBeyondTheAgeOrTheCountNeverLiveOnes) {
  const absl::Time now = kT0 + absl::Hours(2);
  Insert({.id = "expired", .state = v1::FAILED, .end = now - absl::Hours(1) - absl::Seconds(1)});
  Insert({.id = "oldest", .state = v1::FAILED, .end = now - absl::Minutes(30)});
  Insert({.id = "tied-first", .state = v1::FAILED, .end = now - absl::Minutes(10)});
  Insert({.id = "tied-second", .state = v1::FAILED, .end = now - absl::Minutes(10)});
  Insert({.id = "newest", .state = v1::SUCCEEDED, .end = now - absl::Minutes(1)});
  Insert({.id = "queued", .state = v1::QUEUED});
  Insert({.id = "running", .state = v1::RUNNING});
  Transaction([&](pqxx::work& work) { StoreEvent(work, "oldest", Failed(1, "gone")); });
  Transaction([&](pqxx::work& work) {
    PruneFinishedJobs(work, {.max_finished = 3, .max_age = absl::Hours(1)}, now);
  });
  EXPECT_EQ(Ids(), "newest,queued,running,tied-first,tied-second");
  EXPECT_EQ(Sql("SELECT count(*) FROM ispq_job_events"), "0") << "events go with their job";
  // Of two that ended at the same time, the one added first goes first.
  Transaction([&](pqxx::work& work) {
    PruneFinishedJobs(work, {.max_finished = 2, .max_age = absl::Hours(1)}, now);
  });
  EXPECT_EQ(Ids(), "newest,queued,running,tied-second");
}

}  // namespace
}  // namespace ispq::server
