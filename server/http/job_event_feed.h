// A job's events for an HTTP thread that streams them as server-sent events: the blocking
// counterpart of server/job_event_stream.h. cpp-httplib serves a stream by calling a content
// provider on one of its own threads, so the feed is a JobWatcher that wakes that thread, which
// then reads the job's log exactly as a gRPC stream does (Job::NextForStream): the same events,
// numbered the same way, compacted the same way for a slow reader.
#ifndef ISPQ_SERVER_HTTP_JOB_EVENT_FEED_H_
#define ISPQ_SERVER_HTTP_JOB_EVENT_FEED_H_

#include <cstdint>
#include <memory>

#include "absl/base/thread_annotations.h"
#include "absl/synchronization/mutex.h"
#include "absl/time/time.h"
#include "server/job.h"

namespace ispq::server::http {

class JobEventFeed : public JobWatcher, public std::enable_shared_from_this<JobEventFeed> {
 public:
  // Watches `job` from event `from_event` on.
  static std::shared_ptr<JobEventFeed> Watch(std::shared_ptr<Job> job, int64_t from_event);

  JobEventFeed(std::shared_ptr<Job> job, int64_t from_event);

  // The next event (advancing past it) or the final status once the job has ended and every
  // event was delivered; neither if nothing came before `deadline` or Wake was called.
  Job::StreamStep Next(absl::Time deadline);

  // Makes a waiting Next return now (shutdown).
  void Wake();

  void OnJobEvent() override { Wake(); }

 private:
  const std::shared_ptr<Job> job_;
  int64_t next_sequence_;  // only the streaming thread reads and writes it

  absl::Mutex mutex_;
  uint64_t wakeups_ ABSL_GUARDED_BY(mutex_) = 0;
};

}  // namespace ispq::server::http

#endif  // ISPQ_SERVER_HTTP_JOB_EVENT_FEED_H_
