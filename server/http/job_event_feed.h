// SPDX-License-Identifier: Apache-2.0
// A job's events for a server-sent-event stream (server/http/event_stream_route.h): the
// counterpart of server/grpc/job_event_stream.h for a stream that no thread waits on. The stream's
// writer reads the job's log exactly as a gRPC stream does (Job::NextForStream: the same events,
// numbered the same way, compacted the same way for a slow reader); when it has read everything
// there is, it parks (suspends its connection), and the feed, a JobWatcher, resumes it when the
// job appends an event or the server wakes it (keepalives, shutdown).
#ifndef ISPQ_SERVER_HTTP_JOB_EVENT_FEED_H_
#define ISPQ_SERVER_HTTP_JOB_EVENT_FEED_H_

#include <cstdint>
#include <functional>
#include <memory>

#include "absl/base/thread_annotations.h"
#include "absl/functional/function_ref.h"
#include "absl/synchronization/mutex.h"
#include "server/model/job.h"

namespace ispq::server::http {

class JobEventFeed : public JobWatcher, public std::enable_shared_from_this<JobEventFeed> {
 public:
  // Watches `job` from event `from_event` on.
  static std::shared_ptr<JobEventFeed> Watch(std::shared_ptr<Job> job, int64_t from_event);

  JobEventFeed(std::shared_ptr<Job> job, int64_t from_event);

  // The next event (advancing past it) or the final status once the job has ended and every
  // event was delivered; neither if there is nothing yet. Only the stream's writer calls it.
  Job::StreamStep Next();

  // Calls `suspend` and keeps `resume` for the next Wake, unless a Wake came since the last Next
  // (then it returns false and the writer asks Next again): no event can slip in between.
  bool Park(absl::FunctionRef<void()> suspend, std::function<void()> resume);

  // Resumes a parked writer (a new event, a keepalive tick, shutdown).
  void Wake();

  void OnJobEvent() override { Wake(); }

 private:
  const std::shared_ptr<Job> job_;
  int64_t next_sequence_;  // only the writer reads and writes it

  absl::Mutex mutex_;
  uint64_t wakeups_ ABSL_GUARDED_BY(mutex_) = 0;
  uint64_t seen_ ABSL_GUARDED_BY(mutex_) = 0;             // wakeups_ when Next last looked
  std::function<void()> resume_ ABSL_GUARDED_BY(mutex_);  // set while parked
};

}  // namespace ispq::server::http

#endif  // ISPQ_SERVER_HTTP_JOB_EVENT_FEED_H_
