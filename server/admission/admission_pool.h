// SPDX-License-Identifier: Apache-2.0
// The threads that parse and validate the requests that carry meshes, so that gRPC's own threads
// stay free for everything else, health checks above all.
//
// gRPC runs callback handlers on a few threads of its own. When they parsed and validated large
// meshes themselves, a burst of large requests occupied all of them for seconds and a health
// probe waited behind the burst: a busy, healthy server looked dead to its orchestrator. Here a
// fixed number of threads takes that work from a bounded FIFO; when it is full, the request is
// refused at once (RESOURCE_EXHAUSTED, decided on gRPC's thread without parsing). Tasks must not
// block on anything but CPU. The destructor runs the tasks still waiting, then joins.
#ifndef ISPQ_SERVER_ADMISSION_ADMISSION_POOL_H_
#define ISPQ_SERVER_ADMISSION_ADMISSION_POOL_H_

#include <deque>
#include <thread>
#include <vector>

#include "absl/base/thread_annotations.h"
#include "absl/functional/any_invocable.h"
#include "absl/synchronization/mutex.h"

namespace ispq::server {

class AdmissionPool {
 public:
  using Task = absl::AnyInvocable<void() &&>;

  AdmissionPool(int threads, int max_waiting);
  ~AdmissionPool();
  AdmissionPool(const AdmissionPool&) = delete;
  AdmissionPool& operator=(const AdmissionPool&) = delete;

  // Queues `task`; false, dropping it, if `max_waiting` tasks are waiting already.
  bool TrySchedule(Task task);
  // Tasks waiting or running.
  int in_progress() const;
  bool full() const;
  int max_waiting() const { return max_waiting_; }

 private:
  void Work();

  const int max_waiting_;
  mutable absl::Mutex mutex_;
  std::deque<Task> waiting_ ABSL_GUARDED_BY(mutex_);
  int running_ ABSL_GUARDED_BY(mutex_) = 0;
  bool stopping_ ABSL_GUARDED_BY(mutex_) = false;
  std::vector<std::thread> threads_;
};

}  // namespace ispq::server

#endif  // ISPQ_SERVER_ADMISSION_ADMISSION_POOL_H_
