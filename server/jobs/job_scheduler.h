// SPDX-License-Identifier: Apache-2.0
// The job side of the server: admission into the bounded queue, the worker pool that runs jobs,
// the store that answers about them, cancellation, and the draining steps of graceful shutdown.
//
// With the in-memory store, jobs wait in the local bounded queue. With a shared store
// (server/store/postgres/postgres_job_store.h), jobs submitted with SubmitJob wait in the store and
// the workers of every replica claim them (server/jobs/job_claimer.h); only call-bound Quantize
// jobs use the local queue, since they run where their call is. `max_queued_jobs` then bounds the
// jobs waiting in the store for all replicas (checked before each submission, so concurrent
// submissions on several replicas may pass it by a few).
//
// Ownership: the scheduler owns the store, the queue, the claimer and the pool; jobs are shared
// with the streams that watch them. Destruction closes the queue and joins the workers.
#ifndef ISPQ_SERVER_JOBS_JOB_SCHEDULER_H_
#define ISPQ_SERVER_JOBS_JOB_SCHEDULER_H_

#include <memory>
#include <string>

#include "absl/status/statusor.h"
#include "absl/time/time.h"
#include "ispq/v1/service.pb.h"
#include "server/jobs/job_claimer.h"
#include "server/jobs/job_queue.h"
#include "server/jobs/job_source.h"
#include "server/jobs/worker_pool.h"
#include "server/memory/memory_budget.h"
#include "server/metrics/server_metrics.h"
#include "server/model/job.h"
#include "server/model/job_spec.h"
#include "server/store/job_store.h"

namespace ispq::server {

struct SchedulerConfig {
  int workers = 1;
  int max_queued_jobs = 64;
  RetentionPolicy retention;
};

class JobScheduler {
 public:
  // `budget` (may be null) accounts for jobs once they have ended (server/model/job.h). `store`:
  // null for the in-memory store with `config.retention`.
  JobScheduler(const SchedulerConfig& config, ServerMetrics& metrics,
               MemoryBudget* budget = nullptr, std::unique_ptr<JobStore> store = nullptr);
  ~JobScheduler();
  JobScheduler(const JobScheduler&) = delete;
  JobScheduler& operator=(const JobScheduler&) = delete;

  // Creates the job, records it in the store and queues it. `request` is the serialized request
  // (needed by a shared store only, see shared()). Returns the job, or with a shared store the
  // job an earlier request with the same request_id created (server/store/job_store.h).
  // RESOURCE_EXHAUSTED (with a retry hint, see RetryHint and server/jobs/retry_hint.h) when the
  // queue is full; UNAVAILABLE once shutdown has begun or when the store cannot be reached.
  absl::StatusOr<std::shared_ptr<Job>> Submit(JobSpec spec, bool bound_to_call,
                                              const std::string& request = "");
  std::shared_ptr<Job> Find(const std::string& id);
  // OK(nullptr) for an unknown job, UNAVAILABLE when the store cannot answer.
  absl::StatusOr<std::shared_ptr<Job>> Lookup(const std::string& id);
  absl::StatusOr<JobStore::Page> List(const JobStore::Query& query);
  // Drops the retained job that ended first, to make room in the memory budget. Never with a
  // shared store: its retained jobs are not in this process's memory.
  bool EvictOldestFinished() { return !store_->shared() && store_->EvictOldestFinished(); }
  // Whether jobs are kept in a store shared with other replicas.
  bool shared() const { return store_->shared(); }
  // Whether the job store answers now (a cached flag, server/store/job_store.h).
  bool store_reachable() const { return store_->reachable(); }
  // Waits until the store holds what the jobs reported, at most until `deadline`.
  bool FlushStore(absl::Time deadline) { return store_->Flush(deadline); }
  // With a shared store: starts claiming jobs from it, re-admitted with `readmit`.
  void EnableClaiming(JobClaimer::Readmit readmit);
  // Ends a queued job at once (CANCELLED) or interrupts a running one; no effect once done.
  void Cancel(Job& job);

  // How long a client refused for a full queue should wait: the expected time for the queue to
  // move by one job, from the mean solve time so far.
  absl::Duration RetryHint() const;

  // ---- Graceful shutdown, in this order ----
  // Refuses new jobs and ends the queued ones with UNAVAILABLE (they never started, so the
  // client can submit them elsewhere).
  void StopAccepting();
  // Waits for the running jobs to end, at most until `deadline`; whether they all did.
  bool WaitUntilIdle(absl::Time deadline);
  // Interrupts every running job; each ends at its next check with its best result so far.
  void InterruptRunning();

  bool accepting() const { return !queue_.closed(); }
  // Whether a new job would be refused for a full queue.
  bool queue_full() const { return queue_.waiting() >= queue_.capacity(); }

  // Queue, worker and job gauges of `stats`.
  void FillStats(v1::ServerStats& stats) const;

 private:
  ServerMetrics& metrics_;
  MemoryBudget* const budget_;
  std::unique_ptr<JobStore> store_;
  JobClaims* const claims_;  // the store's claims if it is shared, else null
  JobQueue queue_;
  std::unique_ptr<JobClaimer> claimer_;  // with a shared store
  WorkerPool pool_;  // declared last: destroyed (joined) first, while the queue still exists
};

}  // namespace ispq::server

#endif  // ISPQ_SERVER_JOBS_JOB_SCHEDULER_H_
