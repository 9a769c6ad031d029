// SPDX-License-Identifier: Apache-2.0
// The bounded FIFO between the service, which admits jobs, and the workers, which run them.
//
// It also counts the jobs workers hold (popped and not yet marked done), so that "nothing queued
// and nothing running" is one atomic observation, which graceful shutdown waits for. Closing the
// queue refuses new jobs and lets workers exit once it is empty. Thread-safe.
#ifndef ISPQ_SERVER_JOBS_JOB_QUEUE_H_
#define ISPQ_SERVER_JOBS_JOB_QUEUE_H_

#include <deque>
#include <memory>
#include <vector>

#include "absl/base/thread_annotations.h"
#include "absl/status/statusor.h"
#include "absl/synchronization/mutex.h"
#include "absl/time/time.h"
#include "server/jobs/job_source.h"
#include "server/model/job.h"

namespace ispq::server {

class JobQueue final : public JobSource {
 public:
  explicit JobQueue(int capacity);

  // Appends `job`; RESOURCE_EXHAUSTED if `capacity` jobs are waiting, UNAVAILABLE once closed.
  absl::Status Push(std::shared_ptr<Job> job);
  // Blocks until a job is waiting (returned, and counted as held) or the queue is closed and
  // empty (nullptr).
  std::shared_ptr<Job> Pop();
  // A worker has finished with a job it popped (or held).
  void MarkDone();
  // The first waiting job, counted as held, or nullptr at once if none is waiting.
  std::shared_ptr<Job> TryPop();
  // Counts a job that a worker got elsewhere (claimed from a shared store) as held, so that
  // WaitUntilIdle waits for it too.
  void Hold();

  // JobSource: Pop and MarkDone.
  std::shared_ptr<Job> Next() override { return Pop(); }
  void Done() override { MarkDone(); }
  // Takes `job` out of the queue; false if it was not waiting (already popped, or never queued).
  bool Remove(const Job& job);

  // Refuses further pushes and returns the jobs that were waiting, which the caller ends.
  std::vector<std::shared_ptr<Job>> CloseAndDrain();
  // Waits until no job is waiting or held, or until `deadline`; whether it became idle.
  bool WaitUntilIdle(absl::Time deadline);

  int waiting() const;
  bool closed() const;
  int held() const;
  int capacity() const { return capacity_; }

 private:
  const int capacity_;
  mutable absl::Mutex mutex_;
  std::deque<std::shared_ptr<Job>> waiting_ ABSL_GUARDED_BY(mutex_);
  int held_ ABSL_GUARDED_BY(mutex_) = 0;
  bool closed_ ABSL_GUARDED_BY(mutex_) = false;
};

}  // namespace ispq::server

#endif  // ISPQ_SERVER_JOBS_JOB_QUEUE_H_
