// SPDX-License-Identifier: Apache-2.0
#include "server/http/event_streams.h"

#include <utility>
#include <vector>

#include "absl/status/status.h"
#include "absl/strings/str_cat.h"
#include "absl/time/time.h"
#include "server/jobs/retry_hint.h"

namespace ispq::server::http {
namespace {

// Streams last as long as their jobs; a refused watcher may look again in a few seconds.
constexpr absl::Duration kFullRetryHint = absl::Seconds(5);

}  // namespace

EventStreams::EventStreams(int max_streams) : max_streams_(max_streams) {}

absl::StatusOr<std::shared_ptr<JobEventFeed>> EventStreams::Open(std::shared_ptr<Job> job,
                                                                 int64_t from_event) {
  {
    absl::MutexLock lock(&mutex_);
    if (stopping_) return absl::UnavailableError("the server is shutting down");
    if (static_cast<int>(open_.size()) + opening_ >= max_streams_) {
      return ResourceExhaustedWithRetryHint(
          absl::StrCat("too many event streams are open (", max_streams_,
                       "): close one or watch over gRPC"),
          kFullRetryHint);
    }
    ++opening_;  // counted against the bound while the feed is made
  }
  // Outside the lock: the job notifies the new feed at once from AddWatcher.
  std::shared_ptr<JobEventFeed> feed = JobEventFeed::Watch(std::move(job), from_event);
  absl::MutexLock lock(&mutex_);
  --opening_;
  // StopAll may have run meanwhile and would not have woken this one.
  if (stopping_) return absl::UnavailableError("the server is shutting down");
  open_.insert(feed);
  return feed;
}

void EventStreams::Close(const std::shared_ptr<JobEventFeed>& feed) {
  absl::MutexLock lock(&mutex_);
  open_.erase(feed);
}

void EventStreams::WakeAll() {
  std::vector<std::shared_ptr<JobEventFeed>> to_wake;
  {
    absl::MutexLock lock(&mutex_);
    to_wake.assign(open_.begin(), open_.end());
  }
  for (const std::shared_ptr<JobEventFeed>& feed : to_wake) feed->Wake();
}

void EventStreams::StopAll() {
  {
    absl::MutexLock lock(&mutex_);
    stopping_ = true;
  }
  WakeAll();
}

bool EventStreams::stopping() const {
  absl::MutexLock lock(&mutex_);
  return stopping_;
}

int EventStreams::open_streams() const {
  absl::MutexLock lock(&mutex_);
  return static_cast<int>(open_.size());
}

}  // namespace ispq::server::http
