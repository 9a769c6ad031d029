// SPDX-License-Identifier: Apache-2.0
#include "server/store/postgres/postgres_connections.h"

#include <algorithm>
#include <exception>
#include <utility>

#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"
#include "absl/time/clock.h"
#include "server/logging/log_throttle.h"
#include "server/logging/log_value.h"
#include "spdlog/spdlog.h"

namespace ispq::server {
namespace {

// libpq parameters added to a URI that does not set them (connect_timeout too, see
// WithConnectionDefaults). Keepalives notice a vanished peer within about idle + interval *
// count seconds.
constexpr const char* kDefaultParameters[][2] = {
    {"keepalives", "1"},
    {"keepalives_idle", "10"},
    {"keepalives_interval", "5"},
    {"keepalives_count", "3"},
};

LogThrottle& ConnectFailures() {
  static LogThrottle* const throttle = new LogThrottle(absl::Seconds(10));
  return *throttle;
}

}  // namespace

std::string WithConnectionDefaults(const std::string& uri, absl::Duration connect_timeout) {
  std::string result = uri;
  const size_t query = uri.find('?');
  const std::string parameters = query == std::string::npos ? "" : uri.substr(query + 1);
  bool first = query == std::string::npos;
  auto add = [&](const std::string& name, const std::string& value) {
    const std::string key = absl::StrCat(name, "=");
    if (absl::StartsWith(parameters, key) ||
        absl::StrContains(parameters, absl::StrCat("&", key))) {
      return;
    }
    absl::StrAppend(&result, first ? "?" : "&", key, value);
    first = false;
  };
  const int64_t seconds = absl::ToInt64Seconds(absl::Ceil(connect_timeout, absl::Seconds(1)));
  add("connect_timeout", absl::StrCat(std::max<int64_t>(seconds, 2)));
  for (const auto& [name, value] : kDefaultParameters) add(name, value);
  return result;
}

absl::StatusOr<std::shared_ptr<PostgresConnections>> PostgresConnections::Connect(
    PostgresConnectionOptions options) {
  std::shared_ptr<PostgresConnections> pool(
      new PostgresConnections(options.uri, options.operation_timeout));
  std::unique_ptr<pqxx::connection> first;
  try {
    first = std::make_unique<pqxx::connection>(pool->uri_);
    pool->BoundOnTheServer(*first);
  } catch (const std::exception& error) {
    return absl::UnavailableError(
        absl::StrCat("cannot connect to the job store's PostgreSQL database: ", error.what()));
  }
  {
    // No other thread sees the pool yet; the (uncontended) lock keeps the guarded members'
    // accesses checkable by clang's thread-safety analysis.
    absl::MutexLock lock(&pool->mutex_);
    pool->idle_.push_back(std::move(first));
    pool->free_slots_ = options.size > 1 ? options.size - 1 : 0;
  }
  return pool;
}

void PostgresConnections::BoundOnTheServer(pqxx::connection& connection) const {
  // A client that stops between two statements of a transaction (a replica frozen, paused or cut
  // off) keeps its row locks for as long as its connection lives, and every replica's claims skip
  // those rows (FOR UPDATE SKIP LOCKED): its job would never be claimed again. The server ends
  // such a session once it has been idle in a transaction longer than any of ours may last, and
  // stops a statement nobody can wait for any more.
  const std::string milliseconds = absl::StrCat(absl::ToInt64Milliseconds(operation_timeout_));
  connection.set_variable("idle_in_transaction_session_timeout", milliseconds);
  connection.set_variable("statement_timeout", milliseconds);
}

std::unique_ptr<pqxx::connection> PostgresConnections::Borrow(absl::Time deadline,
                                                              std::string& failure) {
  {
    absl::MutexLock lock(&mutex_);
    const bool available = mutex_.AwaitWithDeadline(
        absl::Condition(
            +[](PostgresConnections* pool) ABSL_EXCLUSIVE_LOCKS_REQUIRED(pool->mutex_) {
              return !pool->idle_.empty() || pool->free_slots_ > 0;
            },
            this),
        deadline);
    if (!available) {
      failure = "no connection to the database became free in time";
      return nullptr;
    }
    if (!idle_.empty()) {
      std::unique_ptr<pqxx::connection> connection = std::move(idle_.back());
      idle_.pop_back();
      return connection;
    }
    --free_slots_;
  }
  // Connecting takes a round trip or more (at most connect_timeout): not under the lock. A
  // failure gives the slot back.
  try {
    auto connection = std::make_unique<pqxx::connection>(uri_);
    BoundOnTheServer(*connection);
    return connection;
  } catch (const std::exception& error) {
    failure = error.what();
    if (const auto held_back = ConnectFailures().Admit()) {
      spdlog::warn("event=job_store_connect_failed error={} suppressed={}",
                   QuotedLogValue(error.what()), *held_back);
    }
    Return(nullptr);
    return nullptr;
  }
}

void PostgresConnections::Return(std::unique_ptr<pqxx::connection> connection) {
  absl::MutexLock lock(&mutex_);
  if (connection != nullptr && connection->is_open()) {
    idle_.push_back(std::move(connection));
  } else {
    ++free_slots_;  // dropped: the next borrower connects anew
  }
}

absl::Status PostgresConnections::Run(const std::function<void(pqxx::connection&)>& operation) {
  return Run(operation, operation_timeout_);
}

absl::Status PostgresConnections::Run(const std::function<void(pqxx::connection&)>& operation,
                                      absl::Duration timeout) {
  const absl::Time deadline = absl::Now() + timeout;
  std::string failure = "no connection to the database";
  for (int attempt = 0; attempt < 2 && absl::Now() < deadline; ++attempt) {
    std::unique_ptr<pqxx::connection> connection = Borrow(deadline, failure);
    if (connection == nullptr) break;  // none free in time, or connecting failed
    enum { kDone, kFailed, kBroken, kTimedOut } outcome = kDone;
    {
      SocketDeadlines::Guard guard(deadlines_, connection->sock(), deadline);
      try {
        operation(*connection);
      } catch (const pqxx::broken_connection& error) {
        failure = error.what();
        outcome = kBroken;
      } catch (const std::exception& error) {
        // The transaction was rolled back by pqxx::work's destructor; the connection is fine
        // unless the deadline cut it (checked below).
        failure = error.what();
        outcome = kFailed;
      }
      // Cut by its deadline, possibly just after it succeeded: the socket is shut down.
      if (guard.expired()) outcome = kTimedOut;
    }  // the guard goes before the connection is returned or dropped
    switch (outcome) {
      case kDone:
        Return(std::move(connection));
        return absl::OkStatus();
      case kFailed:
        Return(std::move(connection));
        return absl::UnavailableError(absl::StrCat("the job store's database failed: ", failure));
      case kTimedOut:
        Return(nullptr);
        return absl::UnavailableError(absl::StrCat(
            "the job store's database did not answer within ", absl::FormatDuration(timeout)));
      case kBroken:
        Return(nullptr);  // and try once more on a fresh connection
        break;
    }
  }
  return absl::UnavailableError(absl::StrCat("the job store's database failed: ", failure));
}

}  // namespace ispq::server
