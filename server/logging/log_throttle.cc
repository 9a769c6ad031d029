// SPDX-License-Identifier: Apache-2.0
#include "server/logging/log_throttle.h"

#include "absl/time/clock.h"

namespace ispq::server {

std::optional<int64_t> LogThrottle::Admit(absl::Time now) {
  absl::MutexLock lock(&mutex_);
  if (now < next_) {
    ++held_back_;
    return std::nullopt;
  }
  next_ = now + interval_;
  const int64_t held_back = held_back_;
  held_back_ = 0;
  return held_back;
}

std::optional<int64_t> LogThrottle::Admit() { return Admit(absl::Now()); }

}  // namespace ispq::server
