// SPDX-License-Identifier: Apache-2.0
#include "server/http/connection_deadlines.h"

#include <sys/socket.h>

#include "absl/time/clock.h"

namespace ispq::server::http {

ConnectionDeadlines::ConnectionDeadlines(absl::Duration head_deadline, absl::Duration body_deadline)
    : head_deadline_(head_deadline), body_deadline_(body_deadline) {}

void ConnectionDeadlines::Opened(MHD_Connection* connection, int fd) {
  absl::MutexLock lock(&mutex_);
  open_[connection] = Entry{.fd = fd, .deadline = absl::Now() + head_deadline_};
}

void ConnectionDeadlines::HeadReceived(MHD_Connection* connection) {
  Set(connection, absl::Now() + body_deadline_);
}

void ConnectionDeadlines::RequestReceived(MHD_Connection* connection) {
  Set(connection, absl::InfiniteFuture());
}

void ConnectionDeadlines::RequestDone(MHD_Connection* connection) {
  Set(connection, absl::Now() + head_deadline_);
}

void ConnectionDeadlines::Closed(MHD_Connection* connection) {
  absl::MutexLock lock(&mutex_);
  open_.erase(connection);
}

void ConnectionDeadlines::Set(MHD_Connection* connection, absl::Time deadline) {
  absl::MutexLock lock(&mutex_);
  auto it = open_.find(connection);
  if (it != open_.end()) it->second.deadline = deadline;
}

int ConnectionDeadlines::ShutDownLate(absl::Time now) {
  absl::MutexLock lock(&mutex_);
  int shut_down = 0;
  for (auto& [connection, entry] : open_) {
    if (entry.deadline > now) continue;
    // The socket is still open: Closed, which comes before libmicrohttpd closes it, waits for
    // the lock.
    shutdown(entry.fd, SHUT_RDWR);
    entry.deadline = absl::InfiniteFuture();
    ++shut_down;
  }
  shut_down_total_ += shut_down;
  return shut_down;
}

int ConnectionDeadlines::open() const {
  absl::MutexLock lock(&mutex_);
  return static_cast<int>(open_.size());
}

int64_t ConnectionDeadlines::shut_down_total() const {
  absl::MutexLock lock(&mutex_);
  return shut_down_total_;
}

}  // namespace ispq::server::http
