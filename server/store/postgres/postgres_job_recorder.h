// SPDX-License-Identifier: Apache-2.0
// Records the jobs this replica runs into the PostgreSQL job store (JobEventSink): each change
// becomes one transaction that updates the job's row (state, summary, event count), writes the
// event as its kind's kept event and notifies every replica (NOTIFY), so that watchers anywhere
// see it. The terminal write also drops the stored request and the lease and prunes finished
// jobs beyond the retention policy.
//
// Fenced writes. A job is recorded under the lease it was claimed with: this replica's name and
// the claim's attempt number (the row's `attempts`, which every claim increments). Every write
// requires both in the same statement, so a replica that lost the lease (it stalled past the
// lease and another replica claimed the job, or its job was handed back and claimed again) can
// never write a state, an event or an end over a newer attempt. A write that finds the lease
// gone drops the job's records and abandons the local run (Job::Abandon): its outcome did not
// happen as far as the store is concerned.
//
// Written by a thread of its own. Record only notes the job's latest summary and the latest
// event of each kind (what the store keeps, server/model/job_event_log.h) and returns: the worker
// never waits for the database. The writer writes what is pending, coalescing changes that came
// meanwhile; a write that fails for another reason than a lost lease (the database is down or
// does not answer) is kept and retried with exponential backoff (0.1 s to 5 s) until it lands or
// the lease is found gone, so a run's result survives an outage shorter than the lease. Leases()
// lists the leases to renew: the jobs still running here and those whose end is not written yet.
//
// Draining (shutdown): a run interrupted by the shutdown is given back to the queue (state
// QUEUED, no lease owner, fenced the same way) instead of ending, so that another replica runs
// it; a run whose job a client cancelled meanwhile ends CANCELLED instead.
#ifndef ISPQ_SERVER_STORE_POSTGRES_POSTGRES_JOB_RECORDER_H_
#define ISPQ_SERVER_STORE_POSTGRES_POSTGRES_JOB_RECORDER_H_

#include <array>
#include <atomic>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "absl/base/thread_annotations.h"
#include "absl/container/flat_hash_map.h"
#include "absl/synchronization/mutex.h"
#include "absl/time/time.h"
#include "server/logging/log_throttle.h"
#include "server/model/job.h"
#include "server/model/job_event_sink.h"
#include "server/store/job_store.h"
#include "server/store/postgres/postgres_connections.h"
#include "server/store/postgres/postgres_schema.h"

namespace ispq::server {

// A job's lease in the store: who may write it, under which claim.
struct JobLease {
  std::string id;
  int attempt = 0;  // the row's `attempts` when the lease was taken (0: leased at creation)
};

class PostgresJobRecorder final : public JobEventSink {
 public:
  PostgresJobRecorder(std::shared_ptr<PostgresConnections> connections, std::string replica,
                      RetentionPolicy retention);
  ~PostgresJobRecorder() override { Stop(); }

  // Stops the writer; later records are ignored. Records not written by then are logged and
  // dropped: their leases expire and another replica runs their jobs again (Flush first to
  // avoid it). The store that owns the recorder calls it: jobs may hold the recorder longer.
  void Stop();

  // Records `job`'s changes from now on under `attempt` (see JobLease); the caller makes this
  // recorder the job's event sink. An earlier run of the same job here is abandoned.
  void Track(const std::shared_ptr<Job>& job, int attempt);
  void Record(Job& job, const v1::QuantizeEvent* event) override;

  // The leases to renew: jobs tracked whose end is not written yet.
  std::vector<JobLease> Leases() const;
  // The store says `lease` is no longer this replica's: drop its records, abandon its run.
  void LeaseLost(const JobLease& lease);

  void BeginDraining() { draining_ = true; }
  // Waits until every pending record is written (or found fenced out), at most until
  // `deadline`; whether all were.
  bool Flush(absl::Time deadline);

 private:
  static constexpr int kKinds = 4;  // StoredEventKind
  struct Pending {
    std::weak_ptr<Job> job;
    const Job* run = nullptr;  // which object's records these are (a job may be claimed anew)
    int attempt = 0;
    bool bound_to_call = false;
    v1::Job summary;                                              // the latest
    std::array<std::optional<v1::QuantizeEvent>, kKinds> events;  // the latest of each kind
    bool dirty = false;
    bool release = false;  // draining: give the job back instead of writing its end
    int64_t version = 0;   // counts Record calls, so the writer clears only what it wrote
    absl::Time next_try = absl::InfinitePast();
    absl::Duration backoff;
  };
  enum class Written { kDone, kLeaseLost, kFailed };

  // The writer thread: writes pending records until stopped.
  void WriteLoop();
  // One pending record of `id`, a copy taken under the lock.
  Written Write(const std::string& id, const Pending& record);
  // Gives a drained job back; nullopt if that is not possible (it was cancelled: write its end).
  std::optional<Written> Release(const std::string& id, const Pending& record);
  // Clears what `written` wrote, schedules a retry, or drops a lost lease.
  void Settle(const std::string& id, const Pending& written, Written outcome);
  void AbandonRun(const std::shared_ptr<Job>& job, bool bound_to_call);

  const std::shared_ptr<PostgresConnections> connections_;
  const std::string replica_;
  const RetentionPolicy retention_;
  std::atomic<bool> draining_ = false;
  LogThrottle failures_{absl::Seconds(10)};

  mutable absl::Mutex mutex_;
  absl::flat_hash_map<std::string, Pending> pending_ ABSL_GUARDED_BY(mutex_);
  bool stopping_ ABSL_GUARDED_BY(mutex_) = false;
  std::thread writer_;  // last: started once everything it reads exists
};

}  // namespace ispq::server

#endif  // ISPQ_SERVER_STORE_POSTGRES_POSTGRES_JOB_RECORDER_H_
