// SPDX-License-Identifier: Apache-2.0
// The server-sent-event streams open on the HTTP side: at most a configured number at once (each
// holds a job watcher, a connection and the bytes in flight; none holds a thread: a stream with
// nothing to write is parked, server/http/job_event_feed.h), woken every second so that a
// silent stream can send its keepalive, and all of them ended promptly at shutdown. Thread-safe.
#ifndef ISPQ_SERVER_HTTP_EVENT_STREAMS_H_
#define ISPQ_SERVER_HTTP_EVENT_STREAMS_H_

#include <cstdint>
#include <memory>

#include "absl/base/thread_annotations.h"
#include "absl/container/flat_hash_set.h"
#include "absl/status/statusor.h"
#include "absl/synchronization/mutex.h"
#include "server/http/job_event_feed.h"
#include "server/model/job.h"

namespace ispq::server::http {

class EventStreams {
 public:
  explicit EventStreams(int max_streams);

  // A feed of `job` from `from_event` for a new stream; RESOURCE_EXHAUSTED when `max_streams`
  // are open, UNAVAILABLE once stopping. Call Close with it when the stream ends.
  absl::StatusOr<std::shared_ptr<JobEventFeed>> Open(std::shared_ptr<Job> job, int64_t from_event);
  void Close(const std::shared_ptr<JobEventFeed>& feed);

  // Wakes the open streams (each decides whether it is time for a keepalive).
  void WakeAll();
  // Refuses new streams and wakes the open ones, which then end.
  void StopAll();
  bool stopping() const;
  int open_streams() const;

 private:
  const int max_streams_;
  mutable absl::Mutex mutex_;
  bool stopping_ ABSL_GUARDED_BY(mutex_) = false;
  int opening_ ABSL_GUARDED_BY(mutex_) = 0;
  absl::flat_hash_set<std::shared_ptr<JobEventFeed>> open_ ABSL_GUARDED_BY(mutex_);
};

}  // namespace ispq::server::http

#endif  // ISPQ_SERVER_HTTP_EVENT_STREAMS_H_
