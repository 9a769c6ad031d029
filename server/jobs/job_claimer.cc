// SPDX-License-Identifier: Apache-2.0
#include "server/jobs/job_claimer.h"

#include <utility>

#include "absl/status/status.h"
#include "absl/strings/str_cat.h"
#include "absl/time/clock.h"
#include "server/model/resource_names.h"
#include "spdlog/spdlog.h"

namespace ispq::server {

JobClaimer::JobClaimer(JobQueue& queue, JobClaims& claims, MemoryBudget* budget)
    : queue_(queue), claims_(claims), budget_(budget) {}

void JobClaimer::EnableClaiming(Readmit readmit) {
  {
    absl::MutexLock lock(&mutex_);
    readmit_ = std::move(readmit);
  }
  Wake();
}

void JobClaimer::Wake() {
  absl::MutexLock lock(&mutex_);
  woken_ = true;
}

std::shared_ptr<Job> JobClaimer::Next() {
  while (true) {
    if (std::shared_ptr<Job> local = queue_.TryPop()) return local;
    if (queue_.closed()) return nullptr;  // shutting down: claim nothing more
    Readmit readmit;
    {
      absl::MutexLock lock(&mutex_);
      readmit = readmit_;
    }
    if (readmit) {
      if (std::shared_ptr<Job> claimed = ClaimOne(readmit)) return claimed;
    }
    absl::MutexLock lock(&mutex_);
    mutex_.AwaitWithTimeout(absl::Condition(&woken_), claims_.poll_interval());
    woken_ = false;
  }
}

std::shared_ptr<Job> JobClaimer::ClaimOne(const Readmit& readmit) {
  queue_.Hold();  // before the claim, so that the queue never looks idle while one is taken
  std::optional<JobClaims::Claim> claim = claims_.ClaimNext();
  if (!claim.has_value()) {
    queue_.MarkDone();
    return nullptr;
  }
  absl::StatusOr<JobSpec> spec = readmit(*claim);
  if (!spec.ok()) {
    queue_.MarkDone();
    if (absl::IsResourceExhausted(spec.status()) || absl::IsUnavailable(spec.status())) {
      claims_.Release(*claim);
      // Another replica may have room; this one waits rather than claiming it straight back.
      absl::SleepFor(claims_.poll_interval());
    } else {
      claims_.Fail(*claim, absl::Status(spec.status().code(),
                                        absl::StrCat("the job's request can no longer run: ",
                                                     spec.status().message())));
    }
    return nullptr;
  }
  std::shared_ptr<Job> runner = Job::Resume(claim->id, *std::move(spec), /*bound_to_call=*/false,
                                            claim->create_time, claim->next_sequence, budget_);
  if (claim->cancel_requested) runner->RequestCancel();
  claims_.Adopt(runner, *claim);
  spdlog::info("event=job_claimed job={} attempt={} first_event={}", runner->name(), claim->attempt,
               claim->next_sequence);
  return runner;
}

}  // namespace ispq::server
