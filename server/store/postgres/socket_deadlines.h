// SPDX-License-Identifier: Apache-2.0
// Deadlines for blocking calls on sockets that a library owns (libpq under libpqxx): a thread of
// its own shuts down (shutdown(2), not close) the socket of any call still running at its
// deadline, so that the call fails at once instead of waiting for an answer that may never come.
//
// Why: a database that hangs without closing its connections (a frozen process, a paused VM, a
// partition that drops packets) leaves libpq blocked in recv() for as long as the kernel keeps
// the connection, which is forever when the peer's kernel still acknowledges. Server-side
// timeouts cannot help (the server runs nothing) and libpq has none for queries. Shutting the
// socket down makes the blocked call return an error on the calling thread; the fd stays open
// until its owner closes it, so it can never be reused under the owner's feet.
//
// Thread-safe. Deadlines are checked every `resolution` (a tenth of a second by default).
#ifndef ISPQ_SERVER_STORE_POSTGRES_SOCKET_DEADLINES_H_
#define ISPQ_SERVER_STORE_POSTGRES_SOCKET_DEADLINES_H_

#include <cstdint>
#include <thread>

#include "absl/base/thread_annotations.h"
#include "absl/container/flat_hash_map.h"
#include "absl/synchronization/mutex.h"
#include "absl/time/time.h"

namespace ispq::server {

class SocketDeadlines {
 public:
  explicit SocketDeadlines(absl::Duration resolution = absl::Milliseconds(100));
  ~SocketDeadlines();
  SocketDeadlines(const SocketDeadlines&) = delete;
  SocketDeadlines& operator=(const SocketDeadlines&) = delete;

  // Shuts `fd` down if the guard still exists at `deadline`. The guard must be destroyed before
  // `fd` is closed; whether the deadline cut the call is `expired()`.
  class Guard {
   public:
    Guard(SocketDeadlines& deadlines, int fd, absl::Time deadline);
    ~Guard();
    Guard(const Guard&) = delete;
    Guard& operator=(const Guard&) = delete;
    bool expired() const;

   private:
    SocketDeadlines& deadlines_;
    const int64_t id_;
  };

 private:
  struct Entry {
    int fd = -1;
    absl::Time deadline;
    bool expired = false;
  };
  void Watch();

  const absl::Duration resolution_;
  mutable absl::Mutex mutex_;
  absl::flat_hash_map<int64_t, Entry> entries_ ABSL_GUARDED_BY(mutex_);
  int64_t next_id_ ABSL_GUARDED_BY(mutex_) = 0;
  bool stopping_ ABSL_GUARDED_BY(mutex_) = false;
  std::thread thread_;  // last: started once everything it reads exists
};

}  // namespace ispq::server

#endif  // ISPQ_SERVER_STORE_POSTGRES_SOCKET_DEADLINES_H_
