// SPDX-License-Identifier: Apache-2.0
// A fixed set of PostgreSQL connections (libpqxx) shared by the threads of one replica: each
// operation borrows one connection for the length of one transaction. A pqxx::connection is not
// thread-safe, so a connection is used by one thread at a time; a broken connection (the
// database restarted, a network cut) is replaced on next use, and the operation is tried once
// more on the new one.
//
// Every operation is bounded in time: waiting for a free connection, connecting (libpq's
// connect_timeout) and the operation itself (SocketDeadlines cuts the socket of an operation
// still waiting at its deadline), so that a database that hangs without closing its connections
// never holds a thread much longer than the timeout. Only a pooled connection found broken is
// retried (on a new one); an operation that timed out or could not connect is not: the database
// did not answer, and a second try would only double the wait.
//
// The server bounds them too: a session idle in a transaction for longer than the operation
// timeout is ended (a replica frozen mid-transaction must not keep its row locks, and with them
// its jobs, forever), and so is a statement that runs longer.
//
// Errors never escape as exceptions: an operation that still fails is UNAVAILABLE with the
// database's message, which callers pass on to clients as "retry later". A write cut by its
// deadline may or may not have committed; callers write idempotently
// (server/store/postgres/postgres_job_rows.h).
#ifndef ISPQ_SERVER_STORE_POSTGRES_POSTGRES_CONNECTIONS_H_
#define ISPQ_SERVER_STORE_POSTGRES_POSTGRES_CONNECTIONS_H_

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "absl/base/thread_annotations.h"
#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "absl/synchronization/mutex.h"
#include "absl/time/time.h"
#include "pqxx/pqxx"
#include "server/store/postgres/socket_deadlines.h"

namespace ispq::server {

struct PostgresConnectionOptions {
  std::string uri;  // postgresql://user:password@host:port/database?...
  int size = 8;
  // The longest one operation (a transaction) may take, from the wait for a connection on.
  absl::Duration operation_timeout = absl::Seconds(10);
};

// `uri` with the connection parameters ispq relies on added unless it sets them already:
// connect_timeout (a database that accepts TCP but never answers; whole seconds, at least 2, as
// libpq counts them) and TCP keepalives (a peer that vanished while a connection was idle, e.g.
// the listener's).
std::string WithConnectionDefaults(const std::string& uri, absl::Duration connect_timeout);

class PostgresConnections {
 public:
  // Connects the first of `options.size` connections. UNAVAILABLE naming the database's
  // complaint if it cannot connect.
  static absl::StatusOr<std::shared_ptr<PostgresConnections>> Connect(
      PostgresConnectionOptions options);
  PostgresConnections(const PostgresConnections&) = delete;
  PostgresConnections& operator=(const PostgresConnections&) = delete;

  // Runs `operation` with a borrowed connection (it usually opens one pqxx::work on it), within
  // the operation timeout, or `timeout` if given. Exceptions it throws become UNAVAILABLE
  // (broken connections are retried once first, timed-out operations are not).
  absl::Status Run(const std::function<void(pqxx::connection&)>& operation);
  absl::Status Run(const std::function<void(pqxx::connection&)>& operation, absl::Duration timeout);

  // The URI with WithConnectionDefaults applied (connecting within the operation timeout), for
  // connections of one's own (the listener); with another bound on connecting (a probe).
  const std::string& uri() const { return uri_; }
  std::string UriConnectingWithin(absl::Duration timeout) const {
    return WithConnectionDefaults(given_uri_, timeout);
  }
  // The time bound of operations, and the deadlines that enforce it, for connections of one's
  // own.
  absl::Duration operation_timeout() const { return operation_timeout_; }
  SocketDeadlines& deadlines() { return deadlines_; }

 private:
  PostgresConnections(std::string uri, absl::Duration operation_timeout)
      : given_uri_(std::move(uri)),
        uri_(WithConnectionDefaults(given_uri_, operation_timeout)),
        operation_timeout_(operation_timeout) {}
  // An idle or new connection; null if none is free by `deadline` or connecting failed
  // (`failure` says which).
  std::unique_ptr<pqxx::connection> Borrow(absl::Time deadline, std::string& failure);
  void Return(std::unique_ptr<pqxx::connection> connection);
  // Server-side bounds of a new connection's sessions: no transaction idles and no statement
  // runs longer than the operation timeout.
  void BoundOnTheServer(pqxx::connection& connection) const;

  const std::string given_uri_;
  const std::string uri_;
  const absl::Duration operation_timeout_;
  SocketDeadlines deadlines_;
  absl::Mutex mutex_;
  std::vector<std::unique_ptr<pqxx::connection>> idle_ ABSL_GUARDED_BY(mutex_);
  int free_slots_ ABSL_GUARDED_BY(mutex_) = 0;  // connections neither idle nor borrowed
};

}  // namespace ispq::server

#endif  // ISPQ_SERVER_STORE_POSTGRES_POSTGRES_CONNECTIONS_H_
