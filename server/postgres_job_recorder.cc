#include "server/postgres_job_recorder.h"

#include <utility>

#include "google/protobuf/util/time_util.h"
#include "server/postgres_job_rows.h"
#include "spdlog/spdlog.h"

namespace ispq::server {

PostgresJobRecorder::PostgresJobRecorder(std::shared_ptr<PostgresConnections> connections,
                                         std::string replica, RetentionPolicy retention)
    : connections_(std::move(connections)), replica_(std::move(replica)), retention_(retention) {}

bool PostgresJobRecorder::ReleasedForDrain(Job& job, const v1::QuantizeEvent& event) {
  // Only a run interrupted by the shutdown: not a user's cancellation (it has been recorded as
  // requested in the row, and the next run honours it), not a call-bound job (its call ends here).
  if (!draining_ || job.bound_to_call() || EventKind(event) != StoredEventKind::kTerminal) {
    return false;
  }
  if (event.has_result() && event.result().termination() != v1::INTERRUPTED) return false;
  bool released = false;
  const absl::Status status = connections_->Run([&](pqxx::connection& connection) {
    pqxx::work work(connection);
    const pqxx::result rows = work.exec_params(
        "UPDATE ispq_jobs SET state = $3, lease_owner = NULL, lease_expires = NULL "
        "WHERE id = $1 AND lease_owner = $2 AND NOT cancel_requested RETURNING id",
        job.id(), replica_, static_cast<int>(v1::QUEUED));
    released = !rows.empty();
    if (released) {
      NotifyJobChanged(work, job.id());
      NotifyJobQueued(work);
    }
    work.commit();
  });
  if (!status.ok())
    spdlog::warn("event=job_release_failed job={} error=\"{}\"", job.name(),
                 std::string(status.message()));
  if (released) spdlog::info("event=job_released job={} reason=shutdown", job.name());
  return released;
}

void PostgresJobRecorder::Record(Job& job, const v1::QuantizeEvent* event) {
  if (event != nullptr && ReleasedForDrain(job, *event)) return;
  const v1::Job summary = RowSummary(job);
  const bool done = summary.done();
  const int64_t end_ns =
      done ? google::protobuf::util::TimeUtil::TimestampToNanoseconds(summary.end_time()) : 0;
  bool recorded = false;
  const absl::Status status = connections_->Run([&](pqxx::connection& connection) {
    pqxx::work work(connection);
    const pqxx::result rows = work.exec_params(
        "UPDATE ispq_jobs SET state = $3, summary = $4, next_sequence = $5, "
        "end_time_ns = CASE WHEN $6::boolean THEN $7::bigint ELSE NULL END, "
        "request = CASE WHEN $6::boolean THEN NULL ELSE request END, "
        "lease_owner = CASE WHEN $6::boolean THEN NULL ELSE lease_owner END, "
        "lease_expires = CASE WHEN $6::boolean THEN NULL ELSE lease_expires END "
        "WHERE id = $1 AND state IN (1, 2) AND (lease_owner IS NULL OR lease_owner = $2) "
        "RETURNING id",
        job.id(), replica_, static_cast<int>(summary.state()), ProtoBytes(summary),
        summary.event_count(), done, end_ns);
    recorded = !rows.empty();
    if (!recorded) return;  // rolled back
    if (event != nullptr) StoreEvent(work, job.id(), *event);
    NotifyJobChanged(work, job.id());
    if (done) PruneFinishedJobs(work, retention_, absl::FromUnixNanos(end_ns));
    work.commit();
  });
  if (!status.ok()) {
    // The database is unreachable: the job runs on, and its next event tries again. If the
    // lease expires meanwhile, another replica runs the job again.
    spdlog::warn("event=job_record_failed job={} error=\"{}\"", job.name(),
                 std::string(status.message()));
    return;
  }
  if (!recorded && !job.done()) {
    spdlog::warn("event=job_lease_lost job={} reason=\"another replica runs it now\"", job.name());
    job.RequestCancel();
  }
}

}  // namespace ispq::server
