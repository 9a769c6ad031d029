#include "server/http/operator_routes.h"

#include "server/http/prometheus_text.h"

namespace ispq::server::http {
namespace {

constexpr char kTextType[] = "text/plain; charset=utf-8";
constexpr char kPrometheusType[] = "text/plain; version=0.0.4; charset=utf-8";

void Probe(bool up, const char* up_text, const char* down_text, httplib::Response& response) {
  response.status = up ? 200 : 503;
  response.set_header("Cache-Control", "no-store");
  response.set_content(up ? up_text : down_text, kTextType);
}

}  // namespace

void AddOperatorRoutes(httplib::Server& server, const HttpParts& parts,
                       const EventStreams& streams) {
  server.Get("/healthz", [&parts](const httplib::Request&, httplib::Response& response) {
    Probe(parts.live(), "SERVING\n", "NOT_SERVING: shutting down\n", response);
  });
  server.Get("/readyz", [&parts](const httplib::Request&, httplib::Response& response) {
    Probe(parts.ready(), "READY\n",
          "NOT_READY: shutting down, or a new job would be refused (queue, admission queue or "
          "memory budget full)\n",
          response);
  });
  server.Get("/metrics", [&parts, &streams](const httplib::Request&, httplib::Response& response) {
    const HttpGauges http{.ready = parts.ready(), .open_event_streams = streams.open_streams()};
    response.set_header("Cache-Control", "no-store");
    response.set_content(PrometheusText(parts.service.Stats(), http), kPrometheusType);
  });
}

}  // namespace ispq::server::http
