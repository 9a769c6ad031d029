// SPDX-License-Identifier: Apache-2.0
// The requests the HTTP side refused before their route ran (from the head's checks, or as the
// body passed its limit or the memory budget), counted by HTTP status for /metrics: how often
// and how a server is being sent what it does not take. Thread-safe.
#ifndef ISPQ_SERVER_HTTP_HTTP_REFUSALS_H_
#define ISPQ_SERVER_HTTP_HTTP_REFUSALS_H_

#include <cstdint>
#include <map>

#include "absl/base/thread_annotations.h"
#include "absl/synchronization/mutex.h"

namespace ispq::server::http {

class HttpRefusals {
 public:
  void Count(int http_status);
  // By HTTP status, with the usual ones present even at 0 (so that the series exist).
  std::map<int, int64_t> ByStatus() const;

 private:
  mutable absl::Mutex mutex_;
  std::map<int, int64_t> counts_ ABSL_GUARDED_BY(mutex_);
};

}  // namespace ispq::server::http

#endif  // ISPQ_SERVER_HTTP_HTTP_REFUSALS_H_
