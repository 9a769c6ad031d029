// SPDX-License-Identifier: Apache-2.0
// The routes of the HTTP side and how each is served. A route says, before anything of the
// request's body is read, whether it takes a body, whether its caller must be authenticated,
// whether any Host may ask for it, and on which threads it runs (its lane): only what is cheap
// and never waits runs on the server's own event thread; whatever may wait on the job store or
// parse a large body runs on a small pool of its own (server/http/handler_pool.h), so that no
// slow request holds up the probes.
#ifndef ISPQ_SERVER_HTTP_HTTP_ROUTER_H_
#define ISPQ_SERVER_HTTP_HTTP_ROUTER_H_

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "absl/strings/string_view.h"
#include "server/http/http_message.h"

namespace ispq::server::http {

enum class Lane {
  kInline,    // on the event thread: /healthz, /readyz, the web view's files
  kOperator,  // /metrics, which counts the jobs in the store
  kLookup,    // job lookups, listing, cancel and watch, which may wait on the job store
  kParse,     // job submission, which converts a body of up to --max_message_bytes
};

using RouteHandler =
    std::function<void(HttpRequest& request, const std::shared_ptr<Responder>& responder)>;

struct Route {
  std::string method;   // "GET" (which also serves HEAD) or "POST"
  std::string pattern;  // "/v1/jobs/{id}:cancel": {id} is one segment without '/' or ':'
  Lane lane = Lane::kInline;
  bool authenticated = false;  // HttpRequest::principal is the caller, checked before the body
  bool takes_body = false;     // a JSON body, in HttpRequest::body
  bool any_host = false;       // served whatever the Host header (probes: counts only)
  // The body may also be binary protobuf (Content-Type: application/x-protobuf), which no other
  // site's page can send without asking first, as with JSON (server/http/origin_policy.h).
  bool takes_protobuf = false;
  // What a client is told when the route has not answered within HttpLimits::answer_timeout.
  std::string timeout_message = "the server did not answer in time; retry";
  RouteHandler handle;  // must answer through the responder exactly once
};

class Router {
 public:
  void Add(Route route);
  // The route for `method` and `path`, with `id` set to what its {id} matched; null if none.
  const Route* Match(absl::string_view method, absl::string_view path, std::string* id) const;

 private:
  std::vector<Route> routes_;
};

}  // namespace ispq::server::http

#endif  // ISPQ_SERVER_HTTP_HTTP_ROUTER_H_
