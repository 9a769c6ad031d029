// SPDX-License-Identifier: Apache-2.0
#include "server/http/http_refusals.h"

namespace ispq::server::http {
namespace {

// What the checks of server/http/request_dispatcher.h answer.
constexpr int kUsualStatuses[] = {400, 401, 403, 404, 411, 413, 414, 415, 421, 429, 431, 501, 503};

}  // namespace

void HttpRefusals::Count(int http_status) {
  absl::MutexLock lock(&mutex_);
  ++counts_[http_status];
}

std::map<int, int64_t> HttpRefusals::ByStatus() const {
  std::map<int, int64_t> counts;
  for (const int status : kUsualStatuses) counts[status] = 0;
  absl::MutexLock lock(&mutex_);
  for (const auto& [status, count] : counts_) counts[status] = count;
  return counts;
}

}  // namespace ispq::server::http
