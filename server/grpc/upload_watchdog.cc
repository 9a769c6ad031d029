// SPDX-License-Identifier: Apache-2.0
#include "server/grpc/upload_watchdog.h"

#include <algorithm>

#include "core/invariant.h"

namespace ispq::server {

UploadWatchdog::UploadWatchdog(absl::Duration idle_limit)
    : idle_limit_(idle_limit), checker_([this] { CheckUntilStopped(); }) {}

UploadWatchdog::~UploadWatchdog() {
  {
    absl::MutexLock lock(&mutex_);
    ISPQ_INVARIANT(watched_.empty(), "an upload outlives the server's watchdog");
    stopping_ = true;
  }
  checker_.join();
}

void UploadWatchdog::Watch(grpc::CallbackServerContext* context) {
  absl::MutexLock lock(&mutex_);
  watched_[context] = Watched{absl::Now()};
}

void UploadWatchdog::Touch(grpc::CallbackServerContext* context) {
  absl::MutexLock lock(&mutex_);
  if (auto it = watched_.find(context); it != watched_.end()) it->second.touched = absl::Now();
}

bool UploadWatchdog::Forget(grpc::CallbackServerContext* context) {
  absl::MutexLock lock(&mutex_);
  auto it = watched_.find(context);
  if (it == watched_.end()) return false;
  const bool cancelled = it->second.cancelled;
  watched_.erase(it);
  return cancelled;
}

int64_t UploadWatchdog::dropped() const {
  absl::MutexLock lock(&mutex_);
  return dropped_;
}

void UploadWatchdog::CheckUntilStopped() {
  // Often enough that a stalled upload goes within a tenth of the limit after it.
  const absl::Duration period =
      std::clamp(idle_limit_ / 10, absl::Milliseconds(20), absl::Seconds(1));
  absl::MutexLock lock(&mutex_);
  while (!mutex_.AwaitWithTimeout(absl::Condition(&stopping_), period)) {
    const absl::Time now = absl::Now();
    for (auto& [context, watched] : watched_) {
      if (watched.cancelled || now - watched.touched < idle_limit_) continue;
      // The call stays valid while watched: its reactor forgets it (under this lock) before it
      // is done.
      context->TryCancel();
      watched.cancelled = true;
      ++dropped_;
    }
  }
}

}  // namespace ispq::server
