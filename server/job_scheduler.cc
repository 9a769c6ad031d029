#include "server/job_scheduler.h"

#include <algorithm>
#include <utility>
#include <vector>

#include "absl/status/status.h"
#include "absl/strings/str_cat.h"
#include "absl/time/clock.h"
#include "server/resource_names.h"
#include "server/retry_hint.h"
#include "spdlog/spdlog.h"

namespace ispq::server {
namespace {

constexpr absl::Duration kMinRetryHint = absl::Milliseconds(100);
constexpr absl::Duration kMaxRetryHint = absl::Seconds(60);
constexpr absl::Duration kRetryHintWithoutHistory = absl::Seconds(1);

}  // namespace

JobScheduler::JobScheduler(const SchedulerConfig& config, ServerMetrics& metrics,
                           MemoryBudget* budget)
    : metrics_(metrics),
      budget_(budget),
      store_(config.retention),
      queue_(config.max_queued_jobs),
      pool_(config.workers, queue_, metrics) {}

JobScheduler::~JobScheduler() {
  // Workers exit once the queue is closed and empty; jobs still waiting end as at shutdown.
  StopAccepting();
}

absl::StatusOr<std::shared_ptr<Job>> JobScheduler::Submit(JobSpec spec, bool bound_to_call) {
  const absl::Time now = absl::Now();
  auto job = std::make_shared<Job>(NewResourceId(), std::move(spec), bound_to_call,
                                   queue_.waiting(), now, budget_);
  if (absl::Status pushed = queue_.Push(job); !pushed.ok()) {
    if (absl::IsResourceExhausted(pushed)) {
      metrics_.RecordRejectedQueueFull();
      return ResourceExhaustedWithRetryHint(pushed.message(), RetryHint());
    }
    return pushed;
  }
  // The worker may already run it; the store only needs to know it before Submit returns.
  store_.Add(job, now);
  metrics_.RecordAccepted();
  return job;
}

std::shared_ptr<Job> JobScheduler::Find(const std::string& id) {
  return store_.Find(id, absl::Now());
}

absl::StatusOr<JobStore::Page> JobScheduler::List(const JobStore::Query& query) {
  return store_.List(query, absl::Now());
}

void JobScheduler::Cancel(Job& job) {
  job.RequestCancel();
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
}

bool JobScheduler::WaitUntilIdle(absl::Time deadline) { return queue_.WaitUntilIdle(deadline); }

void JobScheduler::InterruptRunning() {
  for (const std::shared_ptr<Job>& job : store_.ActiveJobs()) job->RequestCancel();
}

void JobScheduler::FillStats(v1::ServerStats& stats) const {
  stats.set_workers(pool_.size());
  stats.set_busy_workers(queue_.held());
  stats.set_queued_jobs(queue_.waiting());
  stats.set_max_queued_jobs(queue_.capacity());
  *stats.mutable_retained_jobs() = store_.CountByState();
}

}  // namespace ispq::server
