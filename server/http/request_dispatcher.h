// SPDX-License-Identifier: Apache-2.0
// What the event thread does with each request libmicrohttpd reads (its request callback): once
// the head is in, it checks everything that can be checked before the body is read, in this
// order, and answers a refusal at once (libmicrohttpd then closes the connection without reading
// the body): the server stopping (503), the target and header sizes (414, 431,
// server/http/request_framing.h), the Host (421, server/http/origin_policy.h), the route (404),
// the body's framing, length and coding (411, 413, 415, 501), the Content-Type (415), the
// Origin (403), the caller (401, on routes that authenticate) and the memory budget for a
// declared length (429). The body is then taken as it arrives, within its limit and the budget
// (server/http/request_body.h); a body refused midway gets its refusal written ahead of the close.
// A complete request goes to its route: on the event thread for the cheap ones, else on the
// route's pool with the connection suspended until the answer (server/http/request_exchange.h).
#ifndef ISPQ_SERVER_HTTP_REQUEST_DISPATCHER_H_
#define ISPQ_SERVER_HTTP_REQUEST_DISPATCHER_H_

#include <microhttpd.h>

#include <atomic>
#include <cstddef>
#include <memory>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "server/http/connection_deadlines.h"
#include "server/http/handler_pool.h"
#include "server/http/http_parts.h"
#include "server/http/http_refusals.h"
#include "server/http/http_router.h"
#include "server/http/origin_policy.h"
#include "server/http/pending_exchanges.h"
#include "server/http/request_exchange.h"
#include "server/http/request_framing.h"
#include "server/http/suspensions.h"

namespace ispq::server::http {

// The pools of the lanes that are not the event thread's.
struct HandlerLanes {
  HandlerPool* operator_lane;
  HandlerPool* lookup;
  HandlerPool* parse;
};

// Everything it refers to must outlive it.
struct DispatcherParts {
  const HttpParts& parts;
  const HttpLimits& limits;
  const Router& router;
  const OriginPolicy& origins;
  HandlerLanes lanes;
  PendingExchanges& pending;
  ConnectionDeadlines& deadlines;
  Suspensions& suspensions;
  HttpRefusals& refusals;
};

class RequestDispatcher {
 public:
  explicit RequestDispatcher(DispatcherParts parts);

  // libmicrohttpd's request callback, with its arguments.
  MHD_Result Handle(MHD_Connection* connection, const char* url, const char* method,
                    const char* upload_data, size_t* upload_data_size, void** context);
  // libmicrohttpd's request-completed callback.
  void Completed(MHD_Connection* connection, void** context);
  // Later requests are answered 503.
  void StopAccepting() { stopping_ = true; }

 private:
  MHD_Result Begin(MHD_Connection* connection, const char* url, const char* method, void** context);
  // Everything checked before the body, in the order above; sets the exchange's route.
  absl::Status CheckHead(RequestExchange& exchange, const HeadSize& size);
  // The stop, the head's size, the Host and the route.
  absl::StatusOr<const Route*> FindRoute(HttpRequest& request, const HeadSize& size) const;
  // The Content-Type, the Origin and the caller (who is then the request's principal).
  absl::Status CheckSender(HttpRequest& request, const Route& route, bool has_body) const;
  MHD_Result Finish(const std::shared_ptr<RequestExchange>& exchange);
  // Hands the request to its route; true if its connection was suspended for the answer.
  bool Dispatch(const std::shared_ptr<RequestExchange>& exchange);
  HandlerPool& PoolOf(Lane lane) const;
  MHD_Result Queue(MHD_Connection* connection, HttpResponse response);

  const DispatcherParts parts_;
  std::atomic<bool> stopping_{false};
};

}  // namespace ispq::server::http

#endif  // ISPQ_SERVER_HTTP_REQUEST_DISPATCHER_H_
