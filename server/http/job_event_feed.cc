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

Job::StreamStep JobEventFeed::Next(absl::Time deadline) {
  uint64_t seen = 0;
  {
    absl::MutexLock lock(&mutex_);
    seen = wakeups_;
  }
  // Read after noting the wakeup count: an event appended after this read bumps the count, so
  // the wait below cannot miss it.
  Job::StreamStep step = job_->NextForStream(next_sequence_);
  if (!step.event.has_value() && !step.final_status.has_value()) {
    absl::MutexLock lock(&mutex_);
    auto woken = [this, seen]() ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_) { return wakeups_ != seen; };
    mutex_.AwaitWithDeadline(absl::Condition(&woken), deadline);
    return step;  // the caller asks again: the event (if any) is read with the lock released
  }
  if (step.event.has_value()) next_sequence_ = step.event->sequence() + 1;
  return step;
}

void JobEventFeed::Wake() {
  absl::MutexLock lock(&mutex_);
  ++wakeups_;
}

}  // namespace ispq::server::http
