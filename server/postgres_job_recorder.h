// Records the jobs this replica created or runs into the PostgreSQL job store (JobEventSink):
// each change becomes one transaction that updates the job's row (state, summary, event count),
// writes the event as its kind's kept event and notifies every replica (NOTIFY), so that
// watchers anywhere see it. The terminal event also drops the stored request and the lease and
// prunes finished jobs beyond the retention policy.
//
// A write is made only while this replica may record the job: the row has no lease owner (a job
// just added) or this replica is it. When another replica took the job over (this one's lease
// expired), the write changes nothing and the local run is interrupted: its result would be a
// duplicate. When draining (shutdown), a job interrupted here is given back to the queue instead
// of ending, so that another replica runs it.
#ifndef ISPQ_SERVER_POSTGRES_JOB_RECORDER_H_
#define ISPQ_SERVER_POSTGRES_JOB_RECORDER_H_

#include <atomic>
#include <memory>
#include <string>

#include "server/job.h"
#include "server/job_event_sink.h"
#include "server/job_store.h"
#include "server/postgres_connections.h"

namespace ispq::server {

class PostgresJobRecorder final : public JobEventSink {
 public:
  PostgresJobRecorder(std::shared_ptr<PostgresConnections> connections, std::string replica,
                      RetentionPolicy retention);

  void Record(Job& job, const v1::QuantizeEvent* event) override;
  void BeginDraining() { draining_ = true; }

 private:
  // Whether `job`'s lease was given back instead of recording `event`.
  bool ReleasedForDrain(Job& job, const v1::QuantizeEvent& event);

  const std::shared_ptr<PostgresConnections> connections_;
  const std::string replica_;
  const RetentionPolicy retention_;
  std::atomic<bool> draining_ = false;
};

}  // namespace ispq::server

#endif  // ISPQ_SERVER_POSTGRES_JOB_RECORDER_H_
