// SPDX-License-Identifier: Apache-2.0
// What operators and orchestrators poll: /healthz follows liveness and /readyz readiness, each on
// its own (a live server may be unready), without authentication and for any Host; /metrics
// counts the service's jobs and the HTTP side's streams, connections and refusals.
#include "server/http/operator_routes.h"

#include <memory>
#include <string>

#include "absl/time/clock.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "server/http/http_router.h"
#include "tests/server/http/http_test_service.h"

namespace ispq::server::http {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;

std::string Header(const HttpResponse& response, const std::string& name) {
  for (const auto& [key, value] : response.headers) {
    if (key == name) return value;
  }
  return "";
}

std::string BodyOf(const HttpResponse& response) {
  return response.body.empty() ? std::string(response.static_body) : response.body;
}

class OperatorRoutesTest : public ::testing::Test {
 protected:
  OperatorRoutesTest() : parts_(service_.parts()) {
    AddOperatorRoutes(
        router_, parts_,
        HttpSideCounts{.streams = streams_, .connections = connections_, .refusals = refusals_});
  }

  HttpResponse Get(const std::string& path) {
    std::string id;
    const Route* route = router_.Match("GET", path, &id);
    EXPECT_NE(route, nullptr) << path;
    if (route == nullptr) return HttpResponse();
    HttpRequest request = RouteRequest("GET", path, "", "");
    auto responder = std::make_shared<RecordingResponder>();
    route->handle(request, responder);
    return responder->WaitForAnswer();
  }

  HttpTestService service_;
  const HttpParts parts_;
  EventStreams streams_{4};
  ConnectionDeadlines connections_{absl::Seconds(10), absl::Seconds(10)};
  HttpRefusals refusals_;
  Router router_;
};

TEST_F(OperatorRoutesTest, AnyHostMayPollThemWithoutCredentials) {
  std::string id;
  for (const char* path : {"/healthz", "/readyz", "/metrics"}) {
    const Route* route = router_.Match("GET", path, &id);
    ASSERT_NE(route, nullptr) << path;
    EXPECT_TRUE(route->any_host) << path;
    EXPECT_FALSE(route->authenticated) << path;
    EXPECT_FALSE(route->takes_body) << path;
  }
  // The probes never wait, so they answer on the event thread; /metrics counts the store's jobs
  // on a thread of its own.
  EXPECT_EQ(router_.Match("GET", "/healthz", &id)->lane, Lane::kInline);
  EXPECT_EQ(router_.Match("GET", "/readyz", &id)->lane, Lane::kInline);
  EXPECT_EQ(router_.Match("GET", "/metrics", &id)->lane, Lane::kOperator);
  EXPECT_EQ(router_.Match("POST", "/healthz", &id), nullptr);
}

TEST_F(OperatorRoutesTest, HealthzFollowsLivenessAndReadyzReadiness) {
  HttpResponse health = Get("/healthz");
  EXPECT_EQ(health.status, 200);
  EXPECT_EQ(BodyOf(health), "SERVING\n");
  EXPECT_EQ(Header(health, "Cache-Control"), "no-store");
  EXPECT_THAT(health.content_type, HasSubstr("text/plain"));
  EXPECT_EQ(Get("/readyz").status, 200);
  EXPECT_EQ(BodyOf(Get("/readyz")), "READY\n");

  // Alive but unready (a full queue): an orchestrator keeps it and sends no traffic.
  service_.ready = false;
  EXPECT_EQ(Get("/healthz").status, 200);
  const HttpResponse unready = Get("/readyz");
  EXPECT_EQ(unready.status, 503);
  EXPECT_THAT(BodyOf(unready), HasSubstr("NOT_READY"));
  EXPECT_EQ(Header(unready, "Cache-Control"), "no-store");

  service_.live = false;
  const HttpResponse dying = Get("/healthz");
  EXPECT_EQ(dying.status, 503);
  EXPECT_THAT(BodyOf(dying), HasSubstr("NOT_SERVING"));

  service_.live = true;
  service_.ready = true;
  EXPECT_EQ(Get("/healthz").status, 200);
  EXPECT_EQ(Get("/readyz").status, 200);
}

TEST_F(OperatorRoutesTest, MetricsCountTheJobsAndTheHttpSide) {
  service_.SubmitOrDie(NotchRequest(), "alice");
  const std::shared_ptr<Job> watched = service_.SubmitOrDie(NotchRequest(), "bob");
  absl::StatusOr<std::shared_ptr<JobEventFeed>> stream = streams_.Open(watched, 0);
  ASSERT_TRUE(stream.ok()) << stream.status();
  int first = 0;
  int second = 0;
  auto* const one = reinterpret_cast<MHD_Connection*>(&first);
  auto* const two = reinterpret_cast<MHD_Connection*>(&second);
  connections_.Opened(one, -1);
  connections_.Opened(two, -1);
  connections_.RequestReceived(two);  // no deadline while it is answered
  ASSERT_EQ(connections_.ShutDownLate(absl::Now() + absl::Hours(1)), 1);  // `one` is late
  refusals_.Count(404);
  refusals_.Count(404);
  refusals_.Count(421);
  service_.ready = false;

  const HttpResponse metrics = Get("/metrics");
  EXPECT_EQ(metrics.status, 200);
  EXPECT_THAT(metrics.content_type, HasSubstr("version=0.0.4"));
  EXPECT_EQ(Header(metrics, "Cache-Control"), "no-store");
  const std::string& text = metrics.body;
  EXPECT_THAT(text, HasSubstr("\nispq_jobs_accepted_total 2\n"));
  EXPECT_THAT(text, HasSubstr("\nispq_queue_length 2\n"));
  EXPECT_THAT(text, HasSubstr("\nispq_ready 0\n"));
  EXPECT_THAT(text, HasSubstr("\nispq_http_event_streams 1\n"));
  EXPECT_THAT(text, HasSubstr("\nispq_http_connections 2\n"));
  EXPECT_THAT(text, HasSubstr("\nispq_http_late_connections_total 1\n"));
  EXPECT_THAT(text, HasSubstr("\nispq_http_refused_total{status=\"404\"} 2\n"));
  EXPECT_THAT(text, HasSubstr("\nispq_http_refused_total{status=\"421\"} 1\n"));

  // Read afresh on every scrape.
  streams_.Close(*stream);
  connections_.Closed(one);
  service_.ready = true;
  const std::string later = Get("/metrics").body;
  EXPECT_THAT(later, HasSubstr("\nispq_http_event_streams 0\n"));
  EXPECT_THAT(later, HasSubstr("\nispq_http_connections 1\n"));
  EXPECT_THAT(later, HasSubstr("\nispq_ready 1\n"));
  EXPECT_THAT(later, Not(HasSubstr("\nispq_ready 0\n")));
}

}  // namespace
}  // namespace ispq::server::http
