// A fixed set of PostgreSQL connections (libpqxx) shared by the threads of one replica: each
// operation borrows one connection for the length of one transaction. A pqxx::connection is not
// thread-safe, so a connection is used by one thread at a time; a broken connection (the
// database restarted, a network cut) is replaced on next use, and the operation is tried once
// more on the new one.
//
// Errors never escape as exceptions: an operation that still fails is UNAVAILABLE with the
// database's message, which callers pass on to clients as "retry later".
#ifndef ISPQ_SERVER_POSTGRES_CONNECTIONS_H_
#define ISPQ_SERVER_POSTGRES_CONNECTIONS_H_

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "absl/base/thread_annotations.h"
#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "absl/synchronization/mutex.h"
#include "pqxx/pqxx"

namespace ispq::server {

class PostgresConnections {
 public:
  // Connects `size` connections to `uri` (postgresql://...). UNAVAILABLE naming the database's
  // complaint if the first cannot connect.
  static absl::StatusOr<std::shared_ptr<PostgresConnections>> Connect(const std::string& uri,
                                                                      int size);
  PostgresConnections(const PostgresConnections&) = delete;
  PostgresConnections& operator=(const PostgresConnections&) = delete;

  // Runs `operation` with a borrowed connection (it usually opens one pqxx::work on it).
  // Exceptions it throws become UNAVAILABLE (broken connections are retried once first).
  absl::Status Run(const std::function<void(pqxx::connection&)>& operation);

  const std::string& uri() const { return uri_; }

 private:
  explicit PostgresConnections(std::string uri) : uri_(std::move(uri)) {}
  std::unique_ptr<pqxx::connection> Borrow();
  void Return(std::unique_ptr<pqxx::connection> connection);

  const std::string uri_;
  absl::Mutex mutex_;
  std::vector<std::unique_ptr<pqxx::connection>> idle_ ABSL_GUARDED_BY(mutex_);
  int free_slots_ ABSL_GUARDED_BY(mutex_) = 0;  // connections neither idle nor borrowed
};

}  // namespace ispq::server

#endif  // ISPQ_SERVER_POSTGRES_CONNECTIONS_H_
