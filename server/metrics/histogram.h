// SPDX-License-Identifier: Apache-2.0
// A fixed-bucket histogram of durations in seconds, exported as a cumulative (Prometheus-style)
// ispq.v1.Histogram. Buckets are chosen once for the whole server: quantization times range
// from milliseconds (small meshes) to the job time limit. Thread-safe.
#ifndef ISPQ_SERVER_METRICS_HISTOGRAM_H_
#define ISPQ_SERVER_METRICS_HISTOGRAM_H_

#include <cstdint>
#include <vector>

#include "absl/base/thread_annotations.h"
#include "absl/synchronization/mutex.h"
#include "ispq/v1/service.pb.h"

namespace ispq::server {

class Histogram {
 public:
  // Upper bounds in seconds, increasing; an implicit last bucket takes everything above.
  explicit Histogram(std::vector<double> upper_bounds);

  // 1 ms to 10 min in steps of about x3.
  static std::vector<double> DefaultSecondsBounds();

  void Observe(double seconds);
  v1::Histogram ToProto() const;

 private:
  const std::vector<double> upper_bounds_;
  mutable absl::Mutex mutex_;
  std::vector<int64_t> counts_ ABSL_GUARDED_BY(mutex_);  // per bucket, not cumulative
  int64_t count_ ABSL_GUARDED_BY(mutex_) = 0;
  double sum_ ABSL_GUARDED_BY(mutex_) = 0;
};

}  // namespace ispq::server

#endif  // ISPQ_SERVER_METRICS_HISTOGRAM_H_
