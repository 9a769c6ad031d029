// SPDX-License-Identifier: Apache-2.0
#include "server/http/pending_exchanges.h"

#include <vector>

#include "absl/status/status.h"
#include "server/http/http_exchange.h"

namespace ispq::server::http {

bool PendingExchanges::Add(const std::shared_ptr<RequestExchange>& exchange) {
  {
    absl::MutexLock lock(&mutex_);
    if (stopping_) return false;
    pending_.emplace(exchange.get(), exchange);
  }
  // Answered by the route, by Expire or by StopAll: it leaves the set then.
  RequestExchange* const key = exchange.get();
  exchange->OnAnswer([this, key] { Remove(key); });
  if (exchange->Answered()) Remove(key);  // before OnAnswer took effect
  return true;
}

void PendingExchanges::Remove(RequestExchange* exchange) {
  absl::MutexLock lock(&mutex_);
  pending_.erase(exchange);
}

void PendingExchanges::Expire(absl::Time now) {
  std::vector<std::shared_ptr<RequestExchange>> late;
  {
    absl::MutexLock lock(&mutex_);
    for (const auto& [key, exchange] : pending_) {
      if (exchange->deadline <= now) late.push_back(exchange);
    }
  }
  for (const std::shared_ptr<RequestExchange>& exchange : late) {
    exchange->Answer(ErrorResponse(absl::DeadlineExceededError(exchange->route->timeout_message)));
  }
}

void PendingExchanges::StopAll() {
  std::vector<std::shared_ptr<RequestExchange>> all;
  {
    absl::MutexLock lock(&mutex_);
    stopping_ = true;
    for (const auto& [key, exchange] : pending_) all.push_back(exchange);
  }
  for (const std::shared_ptr<RequestExchange>& exchange : all) {
    exchange->Answer(ErrorResponse(absl::UnavailableError("the server is shutting down")));
  }
}

int PendingExchanges::size() const {
  absl::MutexLock lock(&mutex_);
  return static_cast<int>(pending_.size());
}

}  // namespace ispq::server::http
