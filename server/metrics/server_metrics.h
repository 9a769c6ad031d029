// SPDX-License-Identifier: Apache-2.0
// Counters the server keeps for operators (GetServerStats): admissions, rejections and evictions,
// jobs ended by final state, and histograms of solve time and queue wait. Updated by the service
// and the workers as things happen; thread-safe and cheap (atomics and one mutex per histogram).
//
// Gauges that describe the present (queue length, busy workers, retained jobs by state) are not
// kept here: they are read from their owners when the stats are requested.
#ifndef ISPQ_SERVER_METRICS_SERVER_METRICS_H_
#define ISPQ_SERVER_METRICS_SERVER_METRICS_H_

#include <atomic>
#include <cstdint>

#include "absl/time/time.h"
#include "ispq/v1/service.pb.h"
#include "server/metrics/histogram.h"

namespace ispq::server {

class ServerMetrics {
 public:
  ServerMetrics();

  void RecordAccepted() { accepted_.fetch_add(1, std::memory_order_relaxed); }
  void RecordRejectedQueueFull() { rejected_queue_full_.fetch_add(1, std::memory_order_relaxed); }
  void RecordRejectedInvalid() { rejected_invalid_.fetch_add(1, std::memory_order_relaxed); }
  void RecordRejectedMemory() { rejected_memory_.fetch_add(1, std::memory_order_relaxed); }
  void RecordEvictedResult() { evicted_results_.fetch_add(1, std::memory_order_relaxed); }
  void RecordEvictedMesh() { evicted_meshes_.fetch_add(1, std::memory_order_relaxed); }
  void RecordStarted(absl::Duration queue_wait);
  // `solve_seconds` < 0 when the job never ran a solve.
  void RecordFinished(v1::JobState final_state, double solve_seconds);

  // Mean solve time of the runs so far (0 before the first), for retry hints.
  double MeanSolveSeconds() const;

  // Fills the counters and histograms of `stats`; the gauges are left to the caller.
  void FillProto(v1::ServerStats& stats) const;

 private:
  std::atomic<int64_t> accepted_{0};
  std::atomic<int64_t> rejected_queue_full_{0};
  std::atomic<int64_t> rejected_invalid_{0};
  std::atomic<int64_t> rejected_memory_{0};
  std::atomic<int64_t> evicted_results_{0};
  std::atomic<int64_t> evicted_meshes_{0};
  std::atomic<int64_t> succeeded_{0};
  std::atomic<int64_t> failed_{0};
  std::atomic<int64_t> cancelled_{0};
  Histogram solve_seconds_;
  Histogram queue_wait_seconds_;
};

}  // namespace ispq::server

#endif  // ISPQ_SERVER_METRICS_SERVER_METRICS_H_
