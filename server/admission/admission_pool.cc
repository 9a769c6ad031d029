// SPDX-License-Identifier: Apache-2.0
#include "server/admission/admission_pool.h"

#include <utility>

#include "server/jobs/thread_priority.h"
#include "server/memory/memory_release.h"

namespace ispq::server {

AdmissionPool::AdmissionPool(int threads, int max_waiting) : max_waiting_(max_waiting) {
  threads_.reserve(threads);
  for (int i = 0; i < threads; ++i) threads_.emplace_back([this] { Work(); });
}

AdmissionPool::~AdmissionPool() {
  {
    absl::MutexLock lock(&mutex_);
    stopping_ = true;
  }
  for (std::thread& thread : threads_) thread.join();
}

bool AdmissionPool::TrySchedule(Task task) {
  absl::MutexLock lock(&mutex_);
  if (static_cast<int>(waiting_.size()) >= max_waiting_) return false;
  waiting_.push_back(std::move(task));
  return true;
}

int AdmissionPool::in_progress() const {
  absl::MutexLock lock(&mutex_);
  return static_cast<int>(waiting_.size()) + running_;
}

bool AdmissionPool::full() const {
  absl::MutexLock lock(&mutex_);
  return static_cast<int>(waiting_.size()) >= max_waiting_;
}

void AdmissionPool::Work() {
  LowerCurrentThreadPriority();
  while (true) {
    Task task;
    {
      absl::MutexLock lock(&mutex_);
      mutex_.Await(absl::Condition(
          +[](AdmissionPool* pool) ABSL_EXCLUSIVE_LOCKS_REQUIRED(pool->mutex_) {
            return !pool->waiting_.empty() || pool->stopping_;
          },
          this));
      if (waiting_.empty()) return;  // stopping, and nothing left to run
      task = std::move(waiting_.front());
      waiting_.pop_front();
      ++running_;
    }
    std::move(task)();
    // The task's captures (a request's bytes and their reservation) go before the trim, so the
    // trim returns their pages too.
    task = nullptr;
    // Parsing and validating a large request allocated and freed many blocks.
    ReleaseFreedMemory();
    absl::MutexLock lock(&mutex_);
    --running_;
  }
}

}  // namespace ispq::server
