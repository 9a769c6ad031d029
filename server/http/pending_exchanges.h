// SPDX-License-Identifier: Apache-2.0
// The requests handed to a route on a pool whose answer has not come yet (their connections
// suspended, server/http/request_exchange.h). The server answers for the route when it takes
// longer than its deadline (504 with the route's timeout message: the route's work is abandoned,
// e.g. a submission stops before parsing) and when it stops (503), so that no connection stays
// suspended: libmicrohttpd cannot be stopped with one. Thread-safe.
#ifndef ISPQ_SERVER_HTTP_PENDING_EXCHANGES_H_
#define ISPQ_SERVER_HTTP_PENDING_EXCHANGES_H_

#include <memory>

#include "absl/base/thread_annotations.h"
#include "absl/container/flat_hash_map.h"
#include "absl/synchronization/mutex.h"
#include "absl/time/time.h"
#include "server/http/request_exchange.h"

namespace ispq::server::http {

class PendingExchanges {
 public:
  // Adds a suspended exchange until it is answered; false once stopping (the caller answers it).
  bool Add(const std::shared_ptr<RequestExchange>& exchange);
  // Answers those past their deadline.
  void Expire(absl::Time now);
  // Refuses new ones and answers all with UNAVAILABLE.
  void StopAll();
  int size() const;

 private:
  void Remove(RequestExchange* exchange);

  mutable absl::Mutex mutex_;
  bool stopping_ ABSL_GUARDED_BY(mutex_) = false;
  absl::flat_hash_map<RequestExchange*, std::shared_ptr<RequestExchange>> pending_
      ABSL_GUARDED_BY(mutex_);
};

}  // namespace ispq::server::http

#endif  // ISPQ_SERVER_HTTP_PENDING_EXCHANGES_H_
