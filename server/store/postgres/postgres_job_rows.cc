// SPDX-License-Identifier: Apache-2.0
#include "server/store/postgres/postgres_job_rows.h"

#include <cstdint>

#include "google/protobuf/util/time_util.h"
#include "server/model/resource_names.h"

namespace ispq::server {
namespace {

using google::protobuf::util::TimeUtil;

template <typename Message>
Message ParseBytes(const pqxx::field& field) {
  Message message;
  const pqxx::binarystring bytes(field);
  message.ParseFromArray(bytes.data(), static_cast<int>(bytes.size()));
  return message;
}

}  // namespace

pqxx::binarystring ProtoBytes(const google::protobuf::MessageLite& message) {
  return pqxx::binarystring(message.SerializeAsString());
}

v1::Job RowSummary(const Job& job) {
  v1::Job summary = job.ToProto(v1::BASIC);
  summary.clear_result();
  summary.clear_error();
  return summary;
}

StoredEventKind EventKind(const v1::QuantizeEvent& event) {
  switch (event.kind_case()) {
    case v1::QuantizeEvent::kAccepted:
      return StoredEventKind::kAccepted;
    case v1::QuantizeEvent::kProgress:
      return StoredEventKind::kProgress;
    case v1::QuantizeEvent::kIntermediate:
      return StoredEventKind::kIntermediate;
    default:
      return StoredEventKind::kTerminal;
  }
}

bool IsTerminal(v1::JobState state) {
  return state == v1::SUCCEEDED || state == v1::FAILED || state == v1::CANCELLED;
}

std::optional<StoredJob> LoadStoredJob(pqxx::work& work, const std::string& id,
                                       absl::Time retained_since, bool terminal_only) {
  const pqxx::result rows = work.exec_params(
      "SELECT state, summary, cancel_requested FROM ispq_jobs WHERE id = $1 AND "
      "(end_time_ns IS NULL OR end_time_ns >= $2)",
      id, absl::ToUnixNanos(retained_since));
  if (rows.empty()) return std::nullopt;
  StoredJob stored;
  stored.summary = ParseBytes<v1::Job>(rows[0][1]);
  const auto state = static_cast<v1::JobState>(rows[0][0].as<int>());
  stored.summary.set_state(state);
  stored.summary.set_done(IsTerminal(state));
  stored.cancel_requested = rows[0][2].as<bool>();
  const pqxx::result events = work.exec_params(
      "SELECT event FROM ispq_job_events WHERE job_id = $1 AND ($2 = false OR kind = $3) "
      "ORDER BY sequence",
      id, terminal_only, static_cast<int>(StoredEventKind::kTerminal));
  for (const pqxx::row& event : events) {
    stored.events.push_back(ParseBytes<v1::QuantizeEvent>(event[0]));
  }
  return stored;
}

void StoreEvent(pqxx::work& work, const std::string& id, const v1::QuantizeEvent& event) {
  const StoredEventKind kind = EventKind(event);
  work.exec_params(
      "INSERT INTO ispq_job_events (job_id, kind, sequence, event) VALUES ($1, $2, $3, $4) "
      "ON CONFLICT (job_id, kind) DO UPDATE SET sequence = EXCLUDED.sequence, "
      "event = EXCLUDED.event",
      id, static_cast<int>(kind), event.sequence(), ProtoBytes(event));
  if (kind == StoredEventKind::kTerminal) {
    work.exec_params("DELETE FROM ispq_job_events WHERE job_id = $1 AND kind = $2", id,
                     static_cast<int>(StoredEventKind::kIntermediate));
  }
}

void EndStoredJob(pqxx::work& work, const std::string& id, const absl::Status& status,
                  absl::Time now) {
  const pqxx::result rows = work.exec_params(
      "SELECT state, summary, next_sequence FROM ispq_jobs WHERE id = $1 FOR UPDATE", id);
  if (rows.empty() || IsTerminal(static_cast<v1::JobState>(rows[0][0].as<int>()))) return;
  const v1::JobState state = absl::IsCancelled(status) ? v1::CANCELLED : v1::FAILED;
  const int64_t sequence = rows[0][2].as<int64_t>();
  v1::QuantizeEvent terminal;
  terminal.set_job(ResourceName(kJobCollection, id));
  terminal.set_sequence(sequence);
  *terminal.mutable_time() = TimeUtil::NanosecondsToTimestamp(absl::ToUnixNanos(now));
  terminal.mutable_error()->set_code(static_cast<int32_t>(status.code()));
  terminal.mutable_error()->set_message(std::string(status.message()));
  v1::Job summary = ParseBytes<v1::Job>(rows[0][1]);
  summary.set_state(state);
  summary.set_done(true);
  *summary.mutable_end_time() = terminal.time();
  summary.set_event_count(sequence + 1);
  work.exec_params(
      "UPDATE ispq_jobs SET state = $2, summary = $3, next_sequence = $4, end_time_ns = $5, "
      "request = NULL, lease_owner = NULL, lease_expires = NULL WHERE id = $1",
      id, static_cast<int>(state), ProtoBytes(summary), sequence + 1, absl::ToUnixNanos(now));
  StoreEvent(work, id, terminal);
  NotifyJobChanged(work, id);
}

void NotifyJobChanged(pqxx::work& work, const std::string& id) {
  work.exec_params("SELECT pg_notify($1, $2)", kJobChangedChannel, id);
}

void NotifyJobQueued(pqxx::work& work) {
  work.exec_params("SELECT pg_notify($1, '')", kJobQueuedChannel);
}

void PruneFinishedJobs(pqxx::work& work, const RetentionPolicy& policy, absl::Time now) {
  work.exec_params("DELETE FROM ispq_jobs WHERE end_time_ns < $1",
                   absl::ToUnixNanos(now - policy.max_age));
  work.exec_params(
      "DELETE FROM ispq_jobs WHERE id IN (SELECT id FROM ispq_jobs WHERE end_time_ns IS NOT NULL "
      "ORDER BY end_time_ns DESC, ordinal DESC OFFSET $1)",
      policy.max_finished);
}

}  // namespace ispq::server
