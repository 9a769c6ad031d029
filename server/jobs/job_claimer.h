// SPDX-License-Identifier: Apache-2.0
// The workers' job source with a shared store (server/store/job_claims.h): first the local queue,
// which holds the call-bound jobs of this replica (a Quantize job runs where its call is), then
// jobs claimed from the store. Between attempts it sleeps until woken (a job was queued here or
// NOTIFYed by any replica) or for the store's poll interval, which is what notices expired
// leases.
//
// A claimed job is re-admitted here from its stored request (parsing, validation and memory
// reservation, as on its first admission): a job this replica cannot hold now (memory) is given
// back for another replica; one whose request no longer admits (its stored mesh was deleted)
// ends FAILED with the reason. Thread-safe; one Next per worker thread.
#ifndef ISPQ_SERVER_JOBS_JOB_CLAIMER_H_
#define ISPQ_SERVER_JOBS_JOB_CLAIMER_H_

#include <functional>
#include <memory>

#include "absl/base/thread_annotations.h"
#include "absl/status/statusor.h"
#include "absl/synchronization/mutex.h"
#include "server/jobs/job_queue.h"
#include "server/jobs/job_source.h"
#include "server/memory/memory_budget.h"
#include "server/model/job_spec.h"
#include "server/store/job_claims.h"

namespace ispq::server {

class JobClaimer final : public JobSource {
 public:
  // Re-admits a claimed job's request as this replica's JobSpec.
  using Readmit = std::function<absl::StatusOr<JobSpec>(const JobClaims::Claim&)>;

  // `queue` and `claims` must outlive the claimer; `budget` (may be null) accounts for ended jobs.
  JobClaimer(JobQueue& queue, JobClaims& claims, MemoryBudget* budget);

  // Starts claiming from the store (until then only the local queue is served).
  void EnableClaiming(Readmit readmit);
  // A job may be waiting: workers look now rather than at the end of their poll interval.
  void Wake();

  std::shared_ptr<Job> Next() override;
  void Done() override { queue_.MarkDone(); }

 private:
  std::shared_ptr<Job> ClaimOne(const Readmit& readmit);

  JobQueue& queue_;
  JobClaims& claims_;
  MemoryBudget* const budget_;
  absl::Mutex mutex_;
  Readmit readmit_ ABSL_GUARDED_BY(mutex_);
  bool woken_ ABSL_GUARDED_BY(mutex_) = false;
};

}  // namespace ispq::server

#endif  // ISPQ_SERVER_JOBS_JOB_CLAIMER_H_
