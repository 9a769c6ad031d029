// SPDX-License-Identifier: Apache-2.0
#include "server/store/postgres/socket_deadlines.h"

#include <sys/socket.h>

#include "absl/time/clock.h"

namespace ispq::server {

SocketDeadlines::SocketDeadlines(absl::Duration resolution)
    : resolution_(resolution), thread_([this] { Watch(); }) {}

SocketDeadlines::~SocketDeadlines() {
  {
    absl::MutexLock lock(&mutex_);
    stopping_ = true;
  }
  thread_.join();
}

SocketDeadlines::Guard::Guard(SocketDeadlines& deadlines, int fd, absl::Time deadline)
    : deadlines_(deadlines), id_([&] {
        absl::MutexLock lock(&deadlines.mutex_);
        const int64_t id = deadlines.next_id_++;
        deadlines.entries_[id] = Entry{.fd = fd, .deadline = deadline};
        return id;
      }()) {}

SocketDeadlines::Guard::~Guard() {
  absl::MutexLock lock(&deadlines_.mutex_);
  deadlines_.entries_.erase(id_);
}

bool SocketDeadlines::Guard::expired() const {
  absl::MutexLock lock(&deadlines_.mutex_);
  const auto it = deadlines_.entries_.find(id_);
  return it != deadlines_.entries_.end() && it->second.expired;
}

void SocketDeadlines::Watch() {
  absl::MutexLock lock(&mutex_);
  while (!mutex_.AwaitWithTimeout(absl::Condition(&stopping_), resolution_)) {
    const absl::Time now = absl::Now();
    for (auto& [id, entry] : entries_) {
      if (entry.expired || now < entry.deadline) continue;
      // Under the lock: the guard, and so the fd, cannot go away meanwhile.
      entry.expired = true;
      if (entry.fd >= 0) ::shutdown(entry.fd, SHUT_RDWR);
    }
  }
}

}  // namespace ispq::server
