// The job side of the server: admission into the bounded queue, the worker pool that runs jobs,
// the store that answers about them, cancellation, and the draining steps of graceful shutdown.
//
// Ownership: the scheduler owns the store, the queue and the pool; jobs are shared with the
// streams that watch them. Destruction closes the queue and joins the workers.
#ifndef ISPQ_SERVER_JOB_SCHEDULER_H_
#define ISPQ_SERVER_JOB_SCHEDULER_H_

#include <memory>
#include <string>

#include "absl/status/statusor.h"
#include "absl/time/time.h"
#include "ispq/v1/service.pb.h"
#include "server/job.h"
#include "server/job_queue.h"
#include "server/job_spec.h"
#include "server/job_store.h"
#include "server/memory_budget.h"
#include "server/server_metrics.h"
#include "server/worker_pool.h"

namespace ispq::server {

struct SchedulerConfig {
  int workers = 1;
  int max_queued_jobs = 64;
  RetentionPolicy retention;
};

class JobScheduler {
 public:
  // `budget` (may be null) accounts for jobs once they have ended (server/job.h).
  JobScheduler(const SchedulerConfig& config, ServerMetrics& metrics,
               MemoryBudget* budget = nullptr);
  ~JobScheduler();
  JobScheduler(const JobScheduler&) = delete;
  JobScheduler& operator=(const JobScheduler&) = delete;

  // Creates the job and queues it. RESOURCE_EXHAUSTED (with a retry hint, see RetryHint and
  // server/retry_hint.h) when the queue is full; UNAVAILABLE once shutdown has begun.
  absl::StatusOr<std::shared_ptr<Job>> Submit(JobSpec spec, bool bound_to_call);
  std::shared_ptr<Job> Find(const std::string& id);
  absl::StatusOr<JobStore::Page> List(const JobStore::Query& query);
  // Drops the retained job that ended first, to make room in the memory budget.
  bool EvictOldestFinished() { return store_.EvictOldestFinished(); }
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
  JobStore store_;
  JobQueue queue_;
  WorkerPool pool_;  // declared last: destroyed (joined) first, while the queue still exists
};

}  // namespace ispq::server

#endif  // ISPQ_SERVER_JOB_SCHEDULER_H_
