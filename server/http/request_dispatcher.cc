// SPDX-License-Identifier: Apache-2.0
#include "server/http/request_dispatcher.h"

#include <string>
#include <utility>

#include "absl/status/statusor.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/string_view.h"
#include "absl/time/clock.h"
#include "server/http/http_exchange.h"
#include "server/http/http_status.h"
#include "server/http/mhd_request.h"
#include "server/http/mhd_response.h"
#include "server/http/request_body.h"
#include "server/http/request_framing.h"

namespace ispq::server::http {
namespace {

using ExchangeHolder = std::shared_ptr<RequestExchange>;

absl::Status ShuttingDown() { return absl::UnavailableError("the server is shutting down"); }

}  // namespace

RequestDispatcher::RequestDispatcher(DispatcherParts parts) : parts_(std::move(parts)) {}

MHD_Result RequestDispatcher::Handle(MHD_Connection* connection, const char* url,
                                     const char* method, const char* upload_data,
                                     size_t* upload_data_size, void** context) {
  if (*context == nullptr) return Begin(connection, url, method, context);
  const ExchangeHolder& exchange = *static_cast<ExchangeHolder*>(*context);
  if (*upload_data_size == 0) return Finish(exchange);
  const absl::Status appended =
      exchange->body().Append(absl::string_view(upload_data, *upload_data_size));
  *upload_data_size = 0;
  if (appended.ok()) return MHD_YES;
  // libmicrohttpd takes no response while a body arrives: the refusal goes ahead of the close.
  parts_.refusals.Count(HttpStatusOf(appended));
  WriteRefusal(connection, appended);
  return MHD_NO;
}

MHD_Result RequestDispatcher::Begin(MHD_Connection* connection, const char* url, const char* method,
                                    void** context) {
  auto exchange = std::make_shared<RequestExchange>(
      connection, RequestBody(parts_.parts.memory, parts_.limits.max_body_bytes),
      parts_.suspensions);
  *context = new ExchangeHolder(exchange);  // deleted in Completed
  parts_.deadlines.HeadReceived(connection);
  const HeadSize size = ReadHead(connection, url, method, exchange->request());
  const absl::Status checked = CheckHead(*exchange, size);
  if (checked.ok()) return MHD_YES;  // the body (if any) comes next
  exchange->route = nullptr;
  parts_.refusals.Count(HttpStatusOf(checked));
  // Queued before the body is read: libmicrohttpd sends it and closes the connection.
  return Queue(connection, ErrorResponse(checked));
}

absl::Status RequestDispatcher::CheckHead(RequestExchange& exchange, const HeadSize& size) {
  HttpRequest& request = exchange.request();
  absl::StatusOr<const Route*> route = FindRoute(request, size);
  if (!route.ok()) return route.status();
  absl::StatusOr<BodyFraming> framing = PlanBody(request, parts_.limits.max_body_bytes);
  if (!framing.ok()) return framing.status();
  const bool has_body = framing->chunked || framing->length > 0;
  if (absl::Status sender = CheckSender(request, **route, has_body); !sender.ok()) return sender;
  if (absl::Status expected = exchange.body().ExpectLength(framing->length); !expected.ok()) {
    return expected;
  }
  exchange.route = *route;
  return absl::OkStatus();
}

absl::StatusOr<const Route*> RequestDispatcher::FindRoute(HttpRequest& request,
                                                          const HeadSize& size) const {
  if (stopping_) return ShuttingDown();
  if (absl::Status sized = CheckHeadSize(size, parts_.limits); !sized.ok()) return sized;
  const Route* route = parts_.router.Match(request.method, request.path, &request.id);
  if (route == nullptr || !route->any_host) {
    if (absl::Status host = parts_.origins.CheckHost(request); !host.ok()) return host;
  }
  if (route == nullptr) {
    return absl::NotFoundError(
        absl::StrCat("no route for ", request.method, " ", request.path.substr(0, 200)));
  }
  return route;
}

absl::Status RequestDispatcher::CheckSender(HttpRequest& request, const Route& route,
                                            bool has_body) const {
  // A POST without credentials must be one no other site's page can send (origin_policy.h).
  if (request.method == "POST" && (has_body || request.Header("authorization").empty())) {
    if (absl::Status type = CheckJsonContentType(request, route.takes_protobuf); !type.ok()) {
      return type;
    }
  }
  if (absl::Status origin = parts_.origins.CheckOrigin(request); !origin.ok()) return origin;
  if (!route.authenticated) return absl::OkStatus();
  absl::StatusOr<Principal> principal = AuthenticateRequest(request, parts_.parts.authenticator);
  if (!principal.ok()) return principal.status();
  request.principal = *std::move(principal);
  return absl::OkStatus();
}

MHD_Result RequestDispatcher::Finish(const std::shared_ptr<RequestExchange>& exchange) {
  if (exchange->route == nullptr) return MHD_NO;  // refused at the head: answered already
  if (!exchange->dispatched) {
    exchange->dispatched = true;
    parts_.deadlines.RequestReceived(exchange->connection());
    HttpRequest& request = exchange->request();
    request.body = exchange->body().TakeBytes();
    request.body_memory = exchange->body().TakeMemory();
    // Suspended: called again once the answer has resumed the connection.
    if (Dispatch(exchange)) return MHD_YES;
  }
  std::optional<HttpResponse> answer = exchange->TakeAnswer();
  if (!answer.has_value()) return MHD_NO;  // a route that did not answer: close
  return Queue(exchange->connection(), *std::move(answer));
}

bool RequestDispatcher::Dispatch(const std::shared_ptr<RequestExchange>& exchange) {
  const Route& route = *exchange->route;
  if (stopping_) {
    exchange->Answer(ErrorResponse(ShuttingDown()));
    return false;
  }
  if (route.lane == Lane::kInline) {
    route.handle(exchange->request(), exchange);
    return false;
  }
  exchange->deadline = absl::Now() + parts_.limits.answer_timeout;
  exchange->Suspend();
  if (!parts_.pending.Add(exchange)) {
    exchange->Answer(ErrorResponse(ShuttingDown()));  // resumes it
    return true;
  }
  const bool posted =
      PoolOf(route.lane).Post([exchange, &route] { route.handle(exchange->request(), exchange); });
  if (!posted) exchange->Answer(ErrorResponse(ShuttingDown()));
  return true;
}

HandlerPool& RequestDispatcher::PoolOf(Lane lane) const {
  switch (lane) {
    case Lane::kOperator:
      return *parts_.lanes.operator_lane;
    case Lane::kParse:
      return *parts_.lanes.parse;
    default:
      return *parts_.lanes.lookup;
  }
}

MHD_Result RequestDispatcher::Queue(MHD_Connection* connection, HttpResponse response) {
  return QueueResponse(connection, std::move(response), parts_.parts.memory.budget(),
                       parts_.suspensions)
             ? MHD_YES
             : MHD_NO;
}

void RequestDispatcher::Completed(MHD_Connection* connection, void** context) {
  delete static_cast<ExchangeHolder*>(*context);
  *context = nullptr;
  // The next request on this connection must come in time too.
  parts_.deadlines.RequestDone(connection);
}

}  // namespace ispq::server::http
