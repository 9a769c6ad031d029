// SPDX-License-Identifier: Apache-2.0
#include "server/metrics/histogram.h"

#include <algorithm>
#include <utility>

namespace ispq::server {

Histogram::Histogram(std::vector<double> upper_bounds)
    : upper_bounds_(std::move(upper_bounds)), counts_(upper_bounds_.size() + 1, 0) {}

std::vector<double> Histogram::DefaultSecondsBounds() {
  return {0.001, 0.003, 0.01, 0.03, 0.1, 0.3, 1, 3, 10, 30, 100, 300, 600};
}

void Histogram::Observe(double seconds) {
  // The first bucket whose upper bound is >= seconds; the overflow bucket otherwise.
  const size_t bucket =
      static_cast<size_t>(std::lower_bound(upper_bounds_.begin(), upper_bounds_.end(), seconds) -
                          upper_bounds_.begin());
  absl::MutexLock lock(&mutex_);
  ++counts_[bucket];
  ++count_;
  sum_ += seconds;
}

v1::Histogram Histogram::ToProto() const {
  v1::Histogram proto;
  absl::MutexLock lock(&mutex_);
  int64_t cumulative = 0;
  for (size_t i = 0; i < upper_bounds_.size(); ++i) {
    cumulative += counts_[i];
    proto.add_upper_bounds(upper_bounds_[i]);
    proto.add_cumulative_counts(cumulative);
  }
  proto.set_count(count_);
  proto.set_sum(sum_);
  return proto;
}

}  // namespace ispq::server
