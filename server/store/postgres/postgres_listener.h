// SPDX-License-Identifier: Apache-2.0
// LISTEN on PostgreSQL notification channels from a thread of its own, with a dedicated
// connection, and hand each notification to a callback. If the connection breaks it reconnects
// and calls the callback with an empty channel: notifications may have been missed, so whoever
// depends on them must look again.
//
// While the database is down, reconnection attempts back off exponentially (0.1 s doubling to
// 10 s, with jitter so that replicas do not reconnect in step) and their failures are logged at
// most every 10 s: the loop must cost neither CPU nor log volume during an outage.
#ifndef ISPQ_SERVER_STORE_POSTGRES_POSTGRES_LISTENER_H_
#define ISPQ_SERVER_STORE_POSTGRES_POSTGRES_LISTENER_H_

#include <functional>
#include <string>
#include <thread>
#include <vector>

#include "absl/synchronization/notification.h"

namespace ispq::server {

class PostgresListener {
 public:
  // (channel, payload); runs on the listener's thread and must not call back into it.
  using Handler = std::function<void(const std::string& channel, const std::string& payload)>;

  // Starts listening and returns once subscribed (or after a few seconds if the database cannot
  // be reached), so that no change made after construction goes unheard; `handler` must stay
  // callable until the destructor returns. `uri` should carry a connect_timeout
  // (WithConnectionDefaults in server/store/postgres/postgres_connections.h).
  PostgresListener(std::string uri, std::vector<std::string> channels, Handler handler);
  // Stops and joins the thread (within a fraction of a second).
  ~PostgresListener();
  PostgresListener(const PostgresListener&) = delete;
  PostgresListener& operator=(const PostgresListener&) = delete;

 private:
  void Run();
  // Listens until the connection breaks (an exception) or stop_.
  void ListenOnce(bool reconnected);

  const std::string uri_;
  const std::vector<std::string> channels_;
  const Handler handler_;
  absl::Notification stop_;
  absl::Notification subscribed_;
  std::thread thread_;  // last: started once everything it reads exists
};

}  // namespace ispq::server

#endif  // ISPQ_SERVER_STORE_POSTGRES_POSTGRES_LISTENER_H_
