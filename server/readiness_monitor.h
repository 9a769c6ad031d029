// SPDX-License-Identifier: Apache-2.0
// Readiness for orchestrators, as the health service "readiness" (grpc.health.v1): SERVING while
// the server would accept a new job, NOT_SERVING while it would refuse it, so that a load balancer
// sends work elsewhere instead of into refusals. Liveness (service "" and "ispq.v1.Quantizer")
// is not affected: a busy server is alive and must not be restarted.
//
// The conditions (queue, admission pool, memory budget) change on many threads, under their own
// locks, and health statuses must not be set under them; so a thread of its own polls them every
// 50 ms and sets the status when it changes.
#ifndef ISPQ_SERVER_READINESS_MONITOR_H_
#define ISPQ_SERVER_READINESS_MONITOR_H_

#include <functional>
#include <thread>

#include "absl/synchronization/notification.h"
#include "grpcpp/health_check_service_interface.h"

namespace ispq::server {

inline constexpr char kReadinessService[] = "readiness";

class ReadinessMonitor {
 public:
  // Sets "readiness" on `health` (which must outlive the monitor) from `ready`, now and on every
  // change until destroyed.
  ReadinessMonitor(grpc::HealthCheckServiceInterface* health, std::function<bool()> ready);
  ~ReadinessMonitor();
  ReadinessMonitor(const ReadinessMonitor&) = delete;
  ReadinessMonitor& operator=(const ReadinessMonitor&) = delete;

 private:
  // Sets the status whenever it differs from `was_ready`, until stopped.
  void Poll(bool was_ready);

  grpc::HealthCheckServiceInterface* const health_;
  const std::function<bool()> ready_;
  absl::Notification stop_;
  std::thread thread_;
};

}  // namespace ispq::server

#endif  // ISPQ_SERVER_READINESS_MONITOR_H_
