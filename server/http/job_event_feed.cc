// SPDX-License-Identifier: Apache-2.0
#include "server/http/job_event_feed.h"

#include <utility>

namespace ispq::server::http {

std::shared_ptr<JobEventFeed> JobEventFeed::Watch(std::shared_ptr<Job> job, int64_t from_event) {
  auto feed = std::make_shared<JobEventFeed>(job, from_event);
  job->AddWatcher(feed);  // held weakly: a feed whose stream ended simply expires
  return feed;
}

JobEventFeed::JobEventFeed(std::shared_ptr<Job> job, int64_t from_event)
    : job_(std::move(job)), next_sequence_(from_event) {}

Job::StreamStep JobEventFeed::Next() {
  {
    absl::MutexLock lock(&mutex_);
    seen_ = wakeups_;
  }
  // Read after noting the wakeup count: an event appended after this read bumps the count, so
  // Park cannot miss it.
  Job::StreamStep step = job_->NextForStream(next_sequence_);
  if (step.event.has_value()) next_sequence_ = step.event->sequence() + 1;
  return step;
}

bool JobEventFeed::Park(absl::FunctionRef<void()> suspend, std::function<void()> resume) {
  absl::MutexLock lock(&mutex_);
  if (wakeups_ != seen_) return false;
  suspend();
  resume_ = std::move(resume);
  return true;
}

void JobEventFeed::Wake() {
  absl::MutexLock lock(&mutex_);
  ++wakeups_;
  if (resume_) {
    // Cheap (it signals the event thread), so it may run under the lock, as a job's watcher must.
    std::function<void()> resume = std::move(resume_);
    resume_ = nullptr;
    resume();
  }
}

}  // namespace ispq::server::http
