// SPDX-License-Identifier: Apache-2.0
// Deadlines for the parts of a request that a client sends: its head must have arrived within
// HttpLimits::head_deadline of its connection (or of the end of its previous request on the same
// connection), and its body within body_deadline of its head, however slowly the bytes trickle
// in. libmicrohttpd only times out connections that are idle, so a client sending a byte every
// few seconds (slowloris) would otherwise keep its connection, and its share of the connection
// limit, forever. A connection past its deadline is shut down (shutdown(2) on its socket, which
// libmicrohttpd then sees as closed by the client and cleans up on its own thread). Connections
// waiting for or receiving their answer have no deadline here. Thread-safe.
#ifndef ISPQ_SERVER_HTTP_CONNECTION_DEADLINES_H_
#define ISPQ_SERVER_HTTP_CONNECTION_DEADLINES_H_

#include <cstdint>

#include "absl/base/thread_annotations.h"
#include "absl/container/flat_hash_map.h"
#include "absl/synchronization/mutex.h"
#include "absl/time/time.h"

struct MHD_Connection;

namespace ispq::server::http {

class ConnectionDeadlines {
 public:
  ConnectionDeadlines(absl::Duration head_deadline, absl::Duration body_deadline);

  // A new connection (`fd` its socket): its first request's head is due.
  void Opened(MHD_Connection* connection, int fd);
  // Before libmicrohttpd closes the socket.
  void Closed(MHD_Connection* connection);
  // A request's head is in: its body is due.
  void HeadReceived(MHD_Connection* connection);
  // A request is complete: no deadline until it has been answered.
  void RequestReceived(MHD_Connection* connection);
  // A request has been answered: the next one's head is due.
  void RequestDone(MHD_Connection* connection);

  // Shuts down the connections past their deadlines; how many.
  int ShutDownLate(absl::Time now);
  int64_t shut_down_total() const;
  int open() const;

 private:
  struct Entry {
    int fd = -1;
    absl::Time deadline = absl::InfiniteFuture();
  };

  void Set(MHD_Connection* connection, absl::Time deadline);

  const absl::Duration head_deadline_;
  const absl::Duration body_deadline_;
  mutable absl::Mutex mutex_;  // held while shutting down, so that no socket closes meanwhile
  absl::flat_hash_map<MHD_Connection*, Entry> open_ ABSL_GUARDED_BY(mutex_);
  int64_t shut_down_total_ ABSL_GUARDED_BY(mutex_) = 0;
};

}  // namespace ispq::server::http

#endif  // ISPQ_SERVER_HTTP_CONNECTION_DEADLINES_H_
