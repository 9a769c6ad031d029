// SPDX-License-Identifier: Apache-2.0
#include "server/jobs/job_scheduler.h"

#include <algorithm>
#include <utility>
#include <vector>

#include "absl/status/status.h"
#include "absl/strings/str_cat.h"
#include "absl/time/clock.h"
#include "server/jobs/retry_hint.h"
#include "server/model/resource_names.h"
#include "server/store/in_memory_job_store.h"
#include "spdlog/spdlog.h"

namespace ispq::server {
namespace {

constexpr absl::Duration kMinRetryHint = absl::Milliseconds(100);
constexpr absl::Duration kMaxRetryHint = absl::Seconds(60);
constexpr absl::Duration kRetryHintWithoutHistory = absl::Seconds(1);

std::unique_ptr<JobStore> OrInMemory(std::unique_ptr<JobStore> store,
                                     const RetentionPolicy& retention) {
  if (store != nullptr) return store;
  return std::make_unique<InMemoryJobStore>(retention);
}

JobSource& SourceOf(JobQueue& queue, std::unique_ptr<JobClaimer>& claimer) {
  if (claimer != nullptr) return *claimer;
  return queue;
}

}  // namespace

JobScheduler::JobScheduler(const SchedulerConfig& config, ServerMetrics& metrics,
                           MemoryBudget* budget, std::unique_ptr<JobStore> store)
    : metrics_(metrics),
      budget_(budget),
      store_(OrInMemory(std::move(store), config.retention)),
      claims_(store_->shared() ? dynamic_cast<JobClaims*>(store_.get()) : nullptr),
      queue_(config.max_queued_jobs),
      claimer_(claims_ != nullptr ? std::make_unique<JobClaimer>(queue_, *claims_, budget)
                                  : nullptr),
      pool_(config.workers, SourceOf(queue_, claimer_), metrics) {
  if (claimer_ != nullptr) {
    claims_->OnClaimable([claimer = claimer_.get()] { claimer->Wake(); });
  }
}

void JobScheduler::EnableClaiming(JobClaimer::Readmit readmit) {
  if (claimer_ != nullptr) claimer_->EnableClaiming(std::move(readmit));
}

JobScheduler::~JobScheduler() {
  // Workers exit once the queue is closed and empty; jobs still waiting end as at shutdown.
  StopAccepting();
}

absl::StatusOr<std::shared_ptr<Job>> JobScheduler::Submit(JobSpec spec, bool bound_to_call,
                                                          const std::string& request) {
  const absl::Time now = absl::Now();
  if (queue_.closed()) {
    return absl::UnavailableError("the server is shutting down and accepts no jobs");
  }
  if (store_->shared()) {
    // Queued in the store for any replica, or (call-bound) here.
    const int waiting = bound_to_call ? queue_.waiting() : claims_->QueuedCount();
    if (waiting >= queue_.capacity()) {
      metrics_.RecordRejectedQueueFull();
      return ResourceExhaustedWithRetryHint(
          absl::StrCat("the job queue is full (", queue_.capacity(), " jobs waiting)"),
          RetryHint());
    }
    auto job = std::make_shared<Job>(NewResourceId(), std::move(spec), bound_to_call,
                                     std::max(waiting, 0), now, budget_);
    absl::StatusOr<std::shared_ptr<Job>> recorded = store_->Add(job, request, now);
    if (!recorded.ok() || *recorded != job) return recorded;  // refused, or a retry's job
    if (bound_to_call) {
      if (absl::Status pushed = queue_.Push(job); !pushed.ok()) {
        job->FinishWithError(pushed, absl::Now());
        return pushed;
      }
    }
    claimer_->Wake();
    metrics_.RecordAccepted();
    return job;
  }
  auto job = std::make_shared<Job>(NewResourceId(), std::move(spec), bound_to_call,
                                   queue_.waiting(), now, budget_);
  if (absl::Status pushed = queue_.Push(job); !pushed.ok()) {
    if (absl::IsResourceExhausted(pushed)) {
      metrics_.RecordRejectedQueueFull();
      return ResourceExhaustedWithRetryHint(pushed.message(), RetryHint());
    }
    return pushed;
  }
  // The worker may already run it; the store only needs to know it before Submit returns. The
  // in-memory store never refuses.
  store_->Add(job, request, now).IgnoreError();
  metrics_.RecordAccepted();
  return job;
}

std::shared_ptr<Job> JobScheduler::Find(const std::string& id) {
  return store_->Find(id, absl::Now());
}

absl::StatusOr<std::shared_ptr<Job>> JobScheduler::Lookup(const std::string& id) {
  return store_->Lookup(id, absl::Now());
}

absl::StatusOr<JobStore::Page> JobScheduler::List(const JobStore::Query& query) {
  return store_->List(query, absl::Now());
}

void JobScheduler::Cancel(Job& job) {
  store_->Cancel(job, absl::Now());
  // If it is still waiting, this thread owns ending it; otherwise the worker does.
  if (queue_.Remove(job)) {
    job.FinishWithError(absl::CancelledError("cancelled while queued"), absl::Now());
    metrics_.RecordFinished(v1::CANCELLED, -1);
    spdlog::info("event=job_end job={} state=CANCELLED reason=\"cancelled while queued\"",
                 job.name());
  }
}

absl::Duration JobScheduler::RetryHint() const {
  const double mean_solve_seconds = metrics_.MeanSolveSeconds();
  if (mean_solve_seconds <= 0) return kRetryHintWithoutHistory;
  const absl::Duration hint = absl::Seconds(mean_solve_seconds / pool_.size());
  return std::clamp(hint, kMinRetryHint, kMaxRetryHint);
}

void JobScheduler::StopAccepting() {
  const std::vector<std::shared_ptr<Job>> drained = queue_.CloseAndDrain();
  for (const std::shared_ptr<Job>& job : drained) {
    job->FinishWithError(
        absl::UnavailableError("the server shut down before the job started; submit it again"),
        absl::Now());
    metrics_.RecordFinished(job->state(), -1);
    spdlog::info("event=job_end job={} state={} reason=\"server shutdown before start\"",
                 job->name(), v1::JobState_Name(job->state()));
  }
  if (claimer_ != nullptr) claimer_->Wake();  // workers waiting for a claim see the queue closed
}

bool JobScheduler::WaitUntilIdle(absl::Time deadline) { return queue_.WaitUntilIdle(deadline); }

void JobScheduler::InterruptRunning() {
  // With a shared store, interrupted jobs go back to it for another replica to run.
  if (claims_ != nullptr) claims_->BeginDraining();
  for (const std::shared_ptr<Job>& job : store_->ActiveJobs()) job->RequestCancel();
}

void JobScheduler::FillStats(v1::ServerStats& stats) const {
  stats.set_workers(pool_.size());
  stats.set_busy_workers(queue_.held());
  stats.set_queued_jobs(claims_ != nullptr ? queue_.waiting() + std::max(claims_->QueuedCount(), 0)
                                           : queue_.waiting());
  stats.set_max_queued_jobs(queue_.capacity());
  *stats.mutable_retained_jobs() = store_->CountByState();
}

}  // namespace ispq::server
