// SPDX-License-Identifier: Apache-2.0
#include "server/store/postgres/postgres_reachability.h"

#include <exception>
#include <string>
#include <utility>

#include "absl/time/clock.h"
#include "server/logging/log_value.h"
#include "spdlog/spdlog.h"

namespace ispq::server {

PostgresReachability::PostgresReachability(PostgresConnections& connections, absl::Duration period,
                                           absl::Duration timeout,
                                           std::function<void()> on_recovered)
    : connections_(connections),
      period_(period),
      timeout_(timeout),
      on_recovered_(std::move(on_recovered)),
      thread_([this] { Probe(); }) {}

PostgresReachability::~PostgresReachability() {
  stop_.Notify();
  thread_.join();
}

bool PostgresReachability::Ping() {
  std::string failure;
  try {
    // Connecting is bounded by the URI's connect_timeout, the query by the deadline.
    if (connection_ == nullptr) {
      connection_ = std::make_unique<pqxx::connection>(connections_.UriConnectingWithin(timeout_));
    }
    bool expired = false;
    {
      SocketDeadlines::Guard guard(connections_.deadlines(), connection_->sock(),
                                   absl::Now() + timeout_);
      try {
        pqxx::nontransaction work(*connection_);
        work.exec("SELECT 1");
      } catch (const std::exception& error) {
        failure = error.what();
      }
      expired = guard.expired();
    }
    if (expired) failure = "no answer in time";
  } catch (const std::exception& error) {
    failure = error.what();
  }
  if (failure.empty()) return true;
  connection_.reset();
  if (reachable()) {
    spdlog::warn("event=job_store_unreachable error={}", QuotedLogValue(failure));
  }
  return false;
}

void PostgresReachability::Probe() {
  absl::Time unreachable_since = absl::InfinitePast();
  do {
    const bool was_reachable = reachable();
    const bool now_reachable = Ping();
    reachable_.store(now_reachable, std::memory_order_relaxed);
    if (was_reachable && !now_reachable) unreachable_since = absl::Now();
    if (!was_reachable && now_reachable) {
      spdlog::info("event=job_store_reachable unreachable_seconds={:.1f}",
                   absl::ToDoubleSeconds(absl::Now() - unreachable_since));
      if (on_recovered_) on_recovered_();
    }
  } while (!stop_.WaitForNotificationWithTimeout(period_));
}

}  // namespace ispq::server
