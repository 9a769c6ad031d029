// SPDX-License-Identifier: Apache-2.0
// At most one log line per interval for a recurring event, with the count of lines held back:
// while the job store's database is down, every worker, the lease thread and the listener fail
// again and again, and one line per failure buried the log (15,000 lines a second per replica
// were measured) and cost the CPU the workers needed.
//
// Usage: a LogThrottle per kind of line, e.g. a member
//   LogThrottle claim_failures_{absl::Seconds(10)};
//   if (const auto held_back = claim_failures_.Admit()) spdlog::warn("... suppressed={}",
//   *held_back);
// Thread-safe.
#ifndef ISPQ_SERVER_LOGGING_LOG_THROTTLE_H_
#define ISPQ_SERVER_LOGGING_LOG_THROTTLE_H_

#include <cstdint>
#include <optional>

#include "absl/base/thread_annotations.h"
#include "absl/synchronization/mutex.h"
#include "absl/time/time.h"

namespace ispq::server {

class LogThrottle {
 public:
  explicit LogThrottle(absl::Duration interval) : interval_(interval) {}

  // Whether to log now: the number of lines held back since the last one logged, or nullopt to
  // hold this one back too.
  std::optional<int64_t> Admit(absl::Time now);
  std::optional<int64_t> Admit();

 private:
  const absl::Duration interval_;
  absl::Mutex mutex_;
  absl::Time next_ ABSL_GUARDED_BY(mutex_) = absl::InfinitePast();
  int64_t held_back_ ABSL_GUARDED_BY(mutex_) = 0;
};

}  // namespace ispq::server

#endif  // ISPQ_SERVER_LOGGING_LOG_THROTTLE_H_
