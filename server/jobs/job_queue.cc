// SPDX-License-Identifier: Apache-2.0
#include "server/jobs/job_queue.h"

#include <algorithm>
#include <utility>

#include "absl/status/status.h"
#include "absl/strings/str_cat.h"

namespace ispq::server {

JobQueue::JobQueue(int capacity) : capacity_(capacity) {}

absl::Status JobQueue::Push(std::shared_ptr<Job> job) {
  absl::MutexLock lock(&mutex_);
  if (closed_) return absl::UnavailableError("the server is shutting down and accepts no jobs");
  if (static_cast<int>(waiting_.size()) >= capacity_) {
    return absl::ResourceExhaustedError(
        absl::StrCat("the job queue is full (", capacity_, " jobs waiting)"));
  }
  waiting_.push_back(std::move(job));
  return absl::OkStatus();
}

std::shared_ptr<Job> JobQueue::Pop() {
  absl::MutexLock lock(&mutex_);
  mutex_.Await(absl::Condition(
      +[](JobQueue* queue) ABSL_EXCLUSIVE_LOCKS_REQUIRED(queue->mutex_) {
        return !queue->waiting_.empty() || queue->closed_;
      },
      this));
  if (waiting_.empty()) return nullptr;
  std::shared_ptr<Job> job = std::move(waiting_.front());
  waiting_.pop_front();
  ++held_;
  return job;
}

std::shared_ptr<Job> JobQueue::TryPop() {
  absl::MutexLock lock(&mutex_);
  if (waiting_.empty()) return nullptr;
  std::shared_ptr<Job> job = std::move(waiting_.front());
  waiting_.pop_front();
  ++held_;
  return job;
}

void JobQueue::Hold() {
  absl::MutexLock lock(&mutex_);
  ++held_;
}

void JobQueue::MarkDone() {
  absl::MutexLock lock(&mutex_);
  --held_;
}

bool JobQueue::Remove(const Job& job) {
  absl::MutexLock lock(&mutex_);
  const auto it =
      std::find_if(waiting_.begin(), waiting_.end(),
                   [&job](const std::shared_ptr<Job>& queued) { return queued.get() == &job; });
  if (it == waiting_.end()) return false;
  waiting_.erase(it);
  return true;
}

std::vector<std::shared_ptr<Job>> JobQueue::CloseAndDrain() {
  absl::MutexLock lock(&mutex_);
  closed_ = true;
  std::vector<std::shared_ptr<Job>> drained(std::make_move_iterator(waiting_.begin()),
                                            std::make_move_iterator(waiting_.end()));
  waiting_.clear();
  return drained;
}

bool JobQueue::WaitUntilIdle(absl::Time deadline) {
  absl::MutexLock lock(&mutex_);
  return mutex_.AwaitWithDeadline(
      absl::Condition(
          +[](JobQueue* queue) ABSL_EXCLUSIVE_LOCKS_REQUIRED(queue->mutex_) {
            return queue->waiting_.empty() && queue->held_ == 0;
          },
          this),
      deadline);
}

int JobQueue::waiting() const {
  absl::MutexLock lock(&mutex_);
  return static_cast<int>(waiting_.size());
}

bool JobQueue::closed() const {
  absl::MutexLock lock(&mutex_);
  return closed_;
}

int JobQueue::held() const {
  absl::MutexLock lock(&mutex_);
  return held_;
}

}  // namespace ispq::server
