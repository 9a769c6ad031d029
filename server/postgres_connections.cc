#include "server/postgres_connections.h"

#include <exception>
#include <utility>

#include "absl/strings/str_cat.h"
#include "spdlog/spdlog.h"

namespace ispq::server {

absl::StatusOr<std::shared_ptr<PostgresConnections>> PostgresConnections::Connect(
    const std::string& uri, int size) {
  std::shared_ptr<PostgresConnections> pool(new PostgresConnections(uri));
  try {
    pool->idle_.push_back(std::make_unique<pqxx::connection>(uri));
  } catch (const std::exception& error) {
    return absl::UnavailableError(
        absl::StrCat("cannot connect to the job store's PostgreSQL database: ", error.what()));
  }
  pool->free_slots_ = size > 1 ? size - 1 : 0;
  return pool;
}

std::unique_ptr<pqxx::connection> PostgresConnections::Borrow() {
  {
    absl::MutexLock lock(&mutex_);
    mutex_.Await(absl::Condition(
        +[](PostgresConnections* pool) ABSL_EXCLUSIVE_LOCKS_REQUIRED(pool->mutex_) {
          return !pool->idle_.empty() || pool->free_slots_ > 0;
        },
        this));
    if (!idle_.empty()) {
      std::unique_ptr<pqxx::connection> connection = std::move(idle_.back());
      idle_.pop_back();
      return connection;
    }
    --free_slots_;
  }
  // Connecting takes a round trip or more: not under the lock. A failure leaves a null
  // connection that Run reports and that Return turns back into a free slot.
  try {
    return std::make_unique<pqxx::connection>(uri_);
  } catch (const std::exception& error) {
    spdlog::warn("event=job_store_connect_failed error=\"{}\"", error.what());
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
  std::string failure = "no connection to the database";
  for (int attempt = 0; attempt < 2; ++attempt) {
    std::unique_ptr<pqxx::connection> connection = Borrow();
    if (connection == nullptr) {
      Return(nullptr);
      continue;
    }
    try {
      operation(*connection);
      Return(std::move(connection));
      return absl::OkStatus();
    } catch (const pqxx::broken_connection& error) {
      failure = error.what();
      connection.reset();
      Return(nullptr);  // and try once more on a fresh connection
    } catch (const std::exception& error) {
      failure = error.what();
      // The transaction was rolled back by pqxx::work's destructor; the connection is fine
      // unless it broke meanwhile.
      Return(std::move(connection));
      break;
    }
  }
  return absl::UnavailableError(absl::StrCat("the job store's database failed: ", failure));
}

}  // namespace ispq::server
