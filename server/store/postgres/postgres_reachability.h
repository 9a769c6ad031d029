// SPDX-License-Identifier: Apache-2.0
// Whether the job store's database answers, as readiness needs it: a thread of its own asks
// `SELECT 1` every `period` on a connection of its own, bounded by `timeout`, and keeps the
// answer in a flag that costs nothing to read. A replica whose database does not answer cannot
// accept, look up or record jobs, so readiness turns NOT_SERVING and load balancers send work
// elsewhere; liveness never looks at it (a restart would not bring the database back).
//
// Transitions are logged once each (not every failed probe), and `on_recovered` runs on the
// probe's thread when the database answers again, so that leases are renewed at once.
#ifndef ISPQ_SERVER_STORE_POSTGRES_POSTGRES_REACHABILITY_H_
#define ISPQ_SERVER_STORE_POSTGRES_POSTGRES_REACHABILITY_H_

#include <atomic>
#include <functional>
#include <memory>
#include <thread>

#include "absl/synchronization/notification.h"
#include "absl/time/time.h"
#include "pqxx/pqxx"
#include "server/store/postgres/postgres_connections.h"

namespace ispq::server {

class PostgresReachability {
 public:
  // Starts probing at once; reachable until a probe says otherwise. `connections` gives the URI
  // and the deadlines, and must outlive this.
  PostgresReachability(PostgresConnections& connections, absl::Duration period,
                       absl::Duration timeout, std::function<void()> on_recovered);
  ~PostgresReachability();
  PostgresReachability(const PostgresReachability&) = delete;
  PostgresReachability& operator=(const PostgresReachability&) = delete;

  bool reachable() const { return reachable_.load(std::memory_order_relaxed); }

 private:
  void Probe();
  bool Ping();

  PostgresConnections& connections_;
  const absl::Duration period_;
  const absl::Duration timeout_;
  const std::function<void()> on_recovered_;
  std::unique_ptr<pqxx::connection> connection_;  // the probe thread's only
  std::atomic<bool> reachable_ = true;
  absl::Notification stop_;
  std::thread thread_;  // last: started once everything it reads exists
};

}  // namespace ispq::server

#endif  // ISPQ_SERVER_STORE_POSTGRES_POSTGRES_REACHABILITY_H_
