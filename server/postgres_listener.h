// LISTEN on PostgreSQL notification channels from a thread of its own, with a dedicated
// connection, and hand each notification to a callback. If the connection breaks it reconnects
// (after a pause) and calls the callback with an empty channel: notifications may have been
// missed, so whoever depends on them must look again.
#ifndef ISPQ_SERVER_POSTGRES_LISTENER_H_
#define ISPQ_SERVER_POSTGRES_LISTENER_H_

#include <atomic>
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
  // callable until the destructor returns.
  PostgresListener(std::string uri, std::vector<std::string> channels, Handler handler);
  // Stops and joins the thread (within a fraction of a second).
  ~PostgresListener();
  PostgresListener(const PostgresListener&) = delete;
  PostgresListener& operator=(const PostgresListener&) = delete;

 private:
  void Run();

  const std::string uri_;
  const std::vector<std::string> channels_;
  const Handler handler_;
  std::atomic<bool> stop_ = false;
  absl::Notification subscribed_;
  std::thread thread_;  // last: started once everything it reads exists
};

}  // namespace ispq::server

#endif  // ISPQ_SERVER_POSTGRES_LISTENER_H_
