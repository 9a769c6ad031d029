// SPDX-License-Identifier: Apache-2.0
// Reading and writing the rows of one job in the PostgreSQL job store
// (server/store/postgres/postgres_schema.h), inside a transaction the caller owns: the pieces that
// the store, its recorder and its claims share.
#ifndef ISPQ_SERVER_STORE_POSTGRES_POSTGRES_JOB_ROWS_H_
#define ISPQ_SERVER_STORE_POSTGRES_POSTGRES_JOB_ROWS_H_

#include <optional>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "absl/time/time.h"
#include "google/protobuf/message_lite.h"
#include "ispq/v1/service.pb.h"
#include "pqxx/pqxx"
#include "server/model/job.h"
#include "server/store/job_store.h"
#include "server/store/postgres/postgres_schema.h"

namespace ispq::server {

// Notification channels: a job's rows changed (payload: its id); a job may be claimable.
inline constexpr char kJobChangedChannel[] = "ispq_job_changed";
inline constexpr char kJobQueuedChannel[] = "ispq_job_queued";
// Cancellation of a running job was requested (payload: its id), for the replica that runs it.
inline constexpr char kJobCancelChannel[] = "ispq_job_cancel";

// A job as stored: its summary (state and done from the row) and its kept events in order.
struct StoredJob {
  v1::Job summary;
  std::vector<v1::QuantizeEvent> events;
  bool cancel_requested = false;
};

pqxx::binarystring ProtoBytes(const google::protobuf::MessageLite& message);
// The summary a job row keeps: the basic view without result or error, which live in the
// terminal event.
v1::Job RowSummary(const Job& job);
StoredEventKind EventKind(const v1::QuantizeEvent& event);
bool IsTerminal(v1::JobState state);

// The job `id` unless unknown or ended before `retained_since`. With `terminal_only`, only the
// terminal event is read (listing needs no more).
std::optional<StoredJob> LoadStoredJob(pqxx::work& work, const std::string& id,
                                       absl::Time retained_since, bool terminal_only = false);

// Writes `event` as its kind's kept event (and drops the intermediate q once terminal).
void StoreEvent(pqxx::work& work, const std::string& id, const v1::QuantizeEvent& event);

// Ends a job that no replica runs (cancelled while queued, orphaned, unrunnable): a terminal
// error event, state CANCELLED for CANCELLED `status`, FAILED otherwise. No effect on an ended
// job. Locks the row.
void EndStoredJob(pqxx::work& work, const std::string& id, const absl::Status& status,
                  absl::Time now);

void NotifyJobChanged(pqxx::work& work, const std::string& id);
void NotifyJobQueued(pqxx::work& work);

// Deletes finished jobs beyond the retention policy (with their events, by cascade).
void PruneFinishedJobs(pqxx::work& work, const RetentionPolicy& policy, absl::Time now);

}  // namespace ispq::server

#endif  // ISPQ_SERVER_STORE_POSTGRES_POSTGRES_JOB_ROWS_H_
