// SPDX-License-Identifier: Apache-2.0
// One request on one libmicrohttpd connection, from its head to its answer: the request as the
// route sees it, its body as it arrives (server/http/request_body.h), its route, and the answer.
// A route on the event thread answers at once; a route on a pool answers later from its thread,
// and the connection is suspended until then (no thread waits; libmicrohttpd neither reads nor
// times it out meanwhile): Answer keeps the response and resumes the connection, and the event
// thread, called again for the request, queues it. Only the first answer counts: a route that
// answers after the server has answered for it (timeout, shutdown) is ignored. The answering
// side is thread-safe; the rest is the event thread's.
#ifndef ISPQ_SERVER_HTTP_REQUEST_EXCHANGE_H_
#define ISPQ_SERVER_HTTP_REQUEST_EXCHANGE_H_

#include <functional>
#include <optional>

#include "absl/base/thread_annotations.h"
#include "absl/synchronization/mutex.h"
#include "absl/time/time.h"
#include "server/http/http_message.h"
#include "server/http/http_router.h"
#include "server/http/request_body.h"
#include "server/http/suspensions.h"

struct MHD_Connection;

namespace ispq::server::http {

class RequestExchange : public Responder {
 public:
  RequestExchange(MHD_Connection* connection, RequestBody body, Suspensions& suspensions);

  HttpRequest& request() { return request_; }
  RequestBody& body() { return body_; }
  MHD_Connection* connection() const { return connection_; }

  const Route* route = nullptr;                  // null: refused at the head
  bool dispatched = false;                       // handed to its route
  absl::Time deadline = absl::InfiniteFuture();  // for the route's answer

  // Suspends the connection until Answer. Event thread, from the request callback.
  void Suspend();
  // Runs `on_answer` (once, on the answering thread, after the answer is kept) when answered.
  void OnAnswer(std::function<void()> on_answer);

  void Answer(HttpResponse response) override;
  bool Answered() const override;
  // The answer, once given (then no more). Event thread.
  std::optional<HttpResponse> TakeAnswer();

 private:
  MHD_Connection* const connection_;
  Suspensions& suspensions_;
  HttpRequest request_;
  RequestBody body_;

  mutable absl::Mutex mutex_;
  bool suspended_ ABSL_GUARDED_BY(mutex_) = false;
  bool answered_ ABSL_GUARDED_BY(mutex_) = false;
  std::optional<HttpResponse> answer_ ABSL_GUARDED_BY(mutex_);
  std::function<void()> on_answer_ ABSL_GUARDED_BY(mutex_);
};

}  // namespace ispq::server::http

#endif  // ISPQ_SERVER_HTTP_REQUEST_EXCHANGE_H_
