// SPDX-License-Identifier: Apache-2.0
#include "server/metrics/server_metrics.h"

namespace ispq::server {

ServerMetrics::ServerMetrics()
    : solve_seconds_(Histogram::DefaultSecondsBounds()),
      queue_wait_seconds_(Histogram::DefaultSecondsBounds()) {}

void ServerMetrics::RecordStarted(absl::Duration queue_wait) {
  queue_wait_seconds_.Observe(absl::ToDoubleSeconds(queue_wait));
}

void ServerMetrics::RecordFinished(v1::JobState final_state, double solve_seconds) {
  switch (final_state) {
    case v1::SUCCEEDED:
      succeeded_.fetch_add(1, std::memory_order_relaxed);
      break;
    case v1::FAILED:
      failed_.fetch_add(1, std::memory_order_relaxed);
      break;
    case v1::CANCELLED:
      cancelled_.fetch_add(1, std::memory_order_relaxed);
      break;
    default:
      break;
  }
  if (solve_seconds >= 0) solve_seconds_.Observe(solve_seconds);
}

double ServerMetrics::MeanSolveSeconds() const {
  const v1::Histogram histogram = solve_seconds_.ToProto();
  return histogram.count() == 0 ? 0.0 : histogram.sum() / static_cast<double>(histogram.count());
}

void ServerMetrics::FillProto(v1::ServerStats& stats) const {
  stats.set_accepted_total(accepted_.load(std::memory_order_relaxed));
  stats.set_rejected_queue_full_total(rejected_queue_full_.load(std::memory_order_relaxed));
  stats.set_rejected_invalid_total(rejected_invalid_.load(std::memory_order_relaxed));
  stats.set_rejected_memory_total(rejected_memory_.load(std::memory_order_relaxed));
  stats.set_evicted_results_total(evicted_results_.load(std::memory_order_relaxed));
  stats.set_evicted_meshes_total(evicted_meshes_.load(std::memory_order_relaxed));
  v1::JobCounts* finished = stats.mutable_finished_total();
  finished->set_succeeded(succeeded_.load(std::memory_order_relaxed));
  finished->set_failed(failed_.load(std::memory_order_relaxed));
  finished->set_cancelled(cancelled_.load(std::memory_order_relaxed));
  *stats.mutable_solve_seconds() = solve_seconds_.ToProto();
  *stats.mutable_queue_wait_seconds() = queue_wait_seconds_.ToProto();
}

}  // namespace ispq::server
