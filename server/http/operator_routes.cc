// SPDX-License-Identifier: Apache-2.0
#include "server/http/operator_routes.h"

#include <memory>

#include "server/http/prometheus_text.h"

namespace ispq::server::http {
namespace {

constexpr char kTextType[] = "text/plain; charset=utf-8";
constexpr char kPrometheusType[] = "text/plain; version=0.0.4; charset=utf-8";

HttpResponse Probe(bool up, const char* up_text, const char* down_text) {
  HttpResponse response;
  response.status = up ? 200 : 503;
  response.headers.emplace_back("Cache-Control", "no-store");
  response.content_type = kTextType;
  response.static_body = up ? up_text : down_text;
  return response;
}

Route OperatorRoute(const char* path, Lane lane, RouteHandler handle) {
  Route route;
  route.method = "GET";
  route.pattern = path;
  route.lane = lane;
  route.any_host = true;
  route.handle = std::move(handle);
  return route;
}

}  // namespace

void AddOperatorRoutes(Router& router, const HttpParts& parts, HttpSideCounts counts) {
  router.Add(OperatorRoute("/healthz", Lane::kInline,
                           [&parts](HttpRequest&, const std::shared_ptr<Responder>& responder) {
                             responder->Answer(
                                 Probe(parts.live(), "SERVING\n", "NOT_SERVING: shutting down\n"));
                           }));
  router.Add(OperatorRoute(
      "/readyz", Lane::kInline,
      [&parts](HttpRequest&, const std::shared_ptr<Responder>& responder) {
        responder->Answer(
            Probe(parts.ready(), "READY\n",
                  "NOT_READY: shutting down, or a new job would be refused (queue, admission queue "
                  "or memory budget full)\n"));
      }));
  router.Add(OperatorRoute(
      "/metrics", Lane::kOperator,
      [&parts, counts](HttpRequest&, const std::shared_ptr<Responder>& responder) {
        const HttpGauges http{.ready = parts.ready(),
                              .open_event_streams = counts.streams.open_streams(),
                              .open_connections = counts.connections.open(),
                              .late_connections_total = counts.connections.shut_down_total(),
                              .refused_total = counts.refusals.ByStatus()};
        HttpResponse response;
        response.headers.emplace_back("Cache-Control", "no-store");
        response.content_type = kPrometheusType;
        response.body = PrometheusText(parts.service.Stats(), http);
        responder->Answer(std::move(response));
      }));
}

}  // namespace ispq::server::http
