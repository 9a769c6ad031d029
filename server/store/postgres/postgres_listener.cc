// SPDX-License-Identifier: Apache-2.0
#include "server/store/postgres/postgres_listener.h"

#include <algorithm>
#include <exception>
#include <memory>
#include <utility>

#include "absl/random/random.h"
#include "absl/time/clock.h"
#include "absl/time/time.h"
#include "pqxx/pqxx"
#include "server/logging/log_throttle.h"
#include "server/logging/log_value.h"
#include "spdlog/spdlog.h"

namespace ispq::server {
namespace {

// How long one wait for notifications lasts: the delay of a stop.
constexpr long kWaitMicroseconds = 200'000;
constexpr absl::Duration kFirstReconnectPause = absl::Milliseconds(100);
constexpr absl::Duration kMaxReconnectPause = absl::Seconds(10);
constexpr absl::Duration kFailureLogInterval = absl::Seconds(10);

class Receiver final : public pqxx::notification_receiver {
 public:
  Receiver(pqxx::connection& connection, const std::string& channel,
           const PostgresListener::Handler& handler)
      : pqxx::notification_receiver(connection, channel), handler_(handler) {}
  void operator()(const std::string& payload, int /*backend_pid*/) override {
    handler_(channel(), payload);
  }

 private:
  const PostgresListener::Handler& handler_;
};

}  // namespace

PostgresListener::PostgresListener(std::string uri, std::vector<std::string> channels,
                                   Handler handler)
    : uri_(std::move(uri)),
      channels_(std::move(channels)),
      handler_(std::move(handler)),
      thread_([this] { Run(); }) {
  subscribed_.WaitForNotificationWithTimeout(absl::Seconds(5));
}

PostgresListener::~PostgresListener() {
  stop_.Notify();
  thread_.join();
}

void PostgresListener::ListenOnce(bool reconnected) {
  pqxx::connection connection(uri_);
  std::vector<std::unique_ptr<Receiver>> receivers;
  for (const std::string& channel : channels_) {
    receivers.push_back(std::make_unique<Receiver>(connection, channel, handler_));
  }
  // LISTEN takes effect once the receivers' commands ran; a query makes sure they did.
  connection.get_notifs();
  if (!subscribed_.HasBeenNotified()) subscribed_.Notify();
  if (reconnected) {
    spdlog::info("event=job_store_listening reconnected=true");
    handler_("", "");  // what was missed must be looked at again
  }
  while (!stop_.HasBeenNotified()) connection.await_notification(0, kWaitMicroseconds);
}

void PostgresListener::Run() {
  absl::BitGen random;
  LogThrottle failures(kFailureLogInterval);
  absl::Duration pause = kFirstReconnectPause;
  bool reconnected = false;
  while (!stop_.HasBeenNotified()) {
    const absl::Time attempt = absl::Now();
    try {
      ListenOnce(reconnected);
    } catch (const std::exception& error) {
      if (const auto held_back = failures.Admit()) {
        spdlog::warn("event=job_store_listen_failed error={} suppressed={} retry_seconds={:.1f}",
                     QuotedLogValue(error.what()), *held_back, absl::ToDoubleSeconds(pause));
      }
    }
    reconnected = true;
    // A connection that lasted a while was a success: the next failure starts the backoff anew.
    if (absl::Now() - attempt > kMaxReconnectPause) pause = kFirstReconnectPause;
    const absl::Duration jittered = pause * absl::Uniform(random, 0.75, 1.25);
    stop_.WaitForNotificationWithTimeout(jittered);
    pause = std::min(2 * pause, kMaxReconnectPause);
  }
}

}  // namespace ispq::server
