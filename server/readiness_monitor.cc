// SPDX-License-Identifier: Apache-2.0
#include "server/readiness_monitor.h"

#include <utility>

#include "absl/time/time.h"
#include "spdlog/spdlog.h"

namespace ispq::server {
namespace {

constexpr absl::Duration kPollInterval = absl::Milliseconds(50);

}  // namespace

ReadinessMonitor::ReadinessMonitor(grpc::HealthCheckServiceInterface* health,
                                   std::function<bool()> ready)
    : health_(health), ready_(std::move(ready)) {
  // Set before returning, so that the service is known from the first probe on.
  const bool ready_now = ready_();
  health_->SetServingStatus(kReadinessService, ready_now);
  thread_ = std::thread([this, ready_now] { Poll(ready_now); });
}

ReadinessMonitor::~ReadinessMonitor() {
  stop_.Notify();
  thread_.join();
}

void ReadinessMonitor::Poll(bool was_ready) {
  while (!stop_.WaitForNotificationWithTimeout(kPollInterval)) {
    const bool ready = ready_();
    if (ready == was_ready) continue;
    health_->SetServingStatus(kReadinessService, ready);
    spdlog::info("event=readiness ready={}", ready);
    was_ready = ready;
  }
}

}  // namespace ispq::server
