#include "server/postgres_listener.h"

#include <chrono>
#include <exception>
#include <memory>
#include <utility>

#include "pqxx/pqxx"
#include "spdlog/spdlog.h"

namespace ispq::server {
namespace {

// How long one wait for notifications lasts: the delay of a stop.
constexpr long kWaitMicroseconds = 200'000;
constexpr auto kReconnectPause = std::chrono::seconds(1);

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
  stop_ = true;
  thread_.join();
}

void PostgresListener::Run() {
  bool first = true;
  while (!stop_) {
    try {
      pqxx::connection connection(uri_);
      std::vector<std::unique_ptr<Receiver>> receivers;
      for (const std::string& channel : channels_) {
        receivers.push_back(std::make_unique<Receiver>(connection, channel, handler_));
      }
      // LISTEN takes effect once the receivers' commands ran; a query makes sure they did.
      connection.get_notifs();
      if (!subscribed_.HasBeenNotified()) subscribed_.Notify();
      if (!first) handler_("", "");  // reconnected: what was missed must be looked at again
      first = false;
      while (!stop_) connection.await_notification(0, kWaitMicroseconds);
    } catch (const std::exception& error) {
      spdlog::warn("event=job_store_listen_failed error=\"{}\"", error.what());
      first = false;
      for (int i = 0; i < 5 && !stop_; ++i) std::this_thread::sleep_for(kReconnectPause / 5);
    }
  }
}

}  // namespace ispq::server
