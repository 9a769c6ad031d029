// SPDX-License-Identifier: Apache-2.0
// The HTTP side as QuantizerServer starts it, on the job service with the in-memory stores:
// Start binds HOST:PORT (port 0 picks one, IPv4 or IPv6) or says why not; the server serves the
// JSON API, the event streams, the probes, /metrics and the web view on its port, to the default
// Hosts only; Stop ends the open streams, stops listening and is idempotent. Each route family
// and the dispatcher have tests of their own; this one checks they are put together.
#include "server/http/http_server.h"

#include <memory>
#include <string>
#include <thread>

#include "absl/status/status.h"
#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "tests/server/http/http_test_service.h"
#include "tests/support/bounded_wait.h"

namespace ispq::server::http {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;

std::string BodyOf(const std::string& answer) {
  const size_t head_end = answer.find("\r\n\r\n");
  return head_end == std::string::npos ? "" : answer.substr(head_end + 4);
}

class HttpServerTest : public ::testing::Test {
 protected:
  void Start(const std::string& address = "127.0.0.1:0") {
    absl::StatusOr<std::unique_ptr<HttpServer>> started =
        HttpServer::Start(address, service_.parts(), HttpLimits());
    ASSERT_TRUE(started.ok()) << started.status();
    server_ = *std::move(started);
    ASSERT_GT(server_->port(), 0);
  }

  // `method` `path` with alice's token, `Connection: close` and Host 127.0.0.1:port unless
  // `headers` names another; the whole answer.
  std::string Send(const std::string& method, const std::string& path,
                   const std::string& headers = "", const std::string& body = "") {
    std::string request =
        absl::StrCat(method, " ", path, " HTTP/1.1\r\nConnection: close\r\nAuthorization: Bearer ",
                     kAliceToken, "\r\n");
    if (!absl::StrContains(headers, "Host:")) {
      absl::StrAppend(&request, "Host: 127.0.0.1:", server_->port(), "\r\n");
    }
    if (method == "POST") {
      absl::StrAppend(&request, "Content-Type: application/json\r\nContent-Length: ", body.size(),
                      "\r\n");
    }
    return RawHttpExchange(server_->port(), absl::StrCat(request, headers, "\r\n", body));
  }

  HttpTestService service_;
  std::unique_ptr<HttpServer> server_;
};

TEST_F(HttpServerTest, StartSaysWhyItCannotListen) {
  for (const char* malformed :
       {"127.0.0.1", ":8080", "127.0.0.1:x", "127.0.0.1:65536", "127.0.0.1:-1", ""}) {
    const auto refused = HttpServer::Start(malformed, service_.parts(), HttpLimits());
    EXPECT_EQ(refused.status().code(), absl::StatusCode::kInvalidArgument) << malformed;
  }
  Start();
  // The port is taken (by the server just started).
  const auto taken = HttpServer::Start(absl::StrCat("127.0.0.1:", server_->port()),
                                       service_.parts(), HttpLimits());
  EXPECT_EQ(taken.status().code(), absl::StatusCode::kUnavailable);
  EXPECT_THAT(std::string(taken.status().message()), HasSubstr("cannot listen"));
  // The first server is unharmed.
  EXPECT_EQ(RawStatus(Send("GET", "/healthz")), 200);
}

TEST_F(HttpServerTest, ServesTheApiTheProbesTheMetricsAndTheWebView) {
  Start();
  const std::string health = Send("GET", "/healthz");
  EXPECT_EQ(RawStatus(health), 200) << health;
  EXPECT_EQ(BodyOf(health), "SERVING\n");
  EXPECT_EQ(RawStatus(Send("GET", "/readyz")), 200);
  const std::string page = Send("GET", "/");
  EXPECT_EQ(RawStatus(page), 200);
  EXPECT_THAT(BodyOf(page), HasSubstr("<html"));

  const std::string submitted = Send("POST", "/v1/jobs", "", ClientJson(NotchRequest("one")));
  ASSERT_EQ(RawStatus(submitted), 200) << submitted;
  const v1::Job job = ParseJson<v1::Job>(BodyOf(submitted));
  EXPECT_EQ(job.owner(), "alice");
  const std::string got = Send("GET", "/v1/" + job.name());
  EXPECT_EQ(RawStatus(got), 200) << got;
  EXPECT_EQ(ParseJson<v1::Job>(BodyOf(got)).name(), job.name());
  const std::string cancelled = Send("POST", "/v1/" + job.name() + ":cancel");
  EXPECT_EQ(RawStatus(cancelled), 200) << cancelled;

  // The job has ended: its stream writes everything and ends.
  const std::string stream = Send("GET", "/v1/" + job.name() + ":watch");
  EXPECT_EQ(RawStatus(stream), 200) << stream;
  EXPECT_THAT(stream, HasSubstr("text/event-stream"));
  EXPECT_THAT(stream, HasSubstr("id: 0\ndata: "));
  EXPECT_THAT(stream, HasSubstr("id: 1\ndata: "));
  EXPECT_THAT(stream, HasSubstr("event: end\ndata: "));

  const std::string metrics = Send("GET", "/metrics");
  EXPECT_EQ(RawStatus(metrics), 200) << metrics;
  EXPECT_THAT(metrics, HasSubstr("\nispq_jobs_accepted_total 1\n"));
  EXPECT_THAT(metrics, HasSubstr("\nispq_http_connections "));
}

// The defaults of --http_allowed_hosts: the listen address and loopback names at the bound port
// (against DNS rebinding); the probes answer any Host.
TEST_F(HttpServerTest, ServesTheDefaultHostsAtItsPortOnly) {
  Start();
  const int port = server_->port();
  for (const std::string& host : {absl::StrCat("127.0.0.1:", port),
                                  absl::StrCat("localhost:", port), absl::StrCat("[::1]:", port)}) {
    EXPECT_EQ(RawStatus(Send("GET", "/v1/jobs", absl::StrCat("Host: ", host, "\r\n"))), 200)
        << host;
  }
  for (const std::string& host : {absl::StrCat("evil.example:", port),
                                  absl::StrCat("localhost:", port + 1), std::string("localhost")}) {
    EXPECT_EQ(RawStatus(Send("GET", "/v1/jobs", absl::StrCat("Host: ", host, "\r\n"))), 421)
        << host;
  }
  EXPECT_EQ(RawStatus(Send("GET", "/healthz", "Host: 10.0.0.7\r\n")), 200);
}

TEST_F(HttpServerTest, ListensOnIpv6) {
  absl::StatusOr<std::unique_ptr<HttpServer>> started =
      HttpServer::Start("[::1]:0", service_.parts(), HttpLimits());
  if (!started.ok()) GTEST_SKIP() << "no IPv6 loopback here: " << started.status();
  const int port = (*started)->port();
  ASSERT_GT(port, 0);
  const std::string answer = RawHttpExchange(
      port,
      absl::StrCat("GET /readyz HTTP/1.1\r\nHost: [::1]:", port, "\r\nConnection: close\r\n\r\n"),
      /*ipv6=*/true);
  EXPECT_EQ(RawStatus(answer), 200) << answer;
}

// A stream of a job that has not ended is cut at Stop (its client reconnects elsewhere), the
// server stops listening, and Stop may be called again (the destructor does).
TEST_F(HttpServerTest, StopEndsTheOpenStreamsAndStopsListening) {
  Start();
  const std::string queued =
      BodyOf(Send("POST", "/v1/jobs", "", ClientJson(NotchRequest("stays-queued"))));
  const std::string name = ParseJson<v1::Job>(queued).name();
  ASSERT_FALSE(name.empty()) << queued;
  std::string stream;
  std::thread watcher([&] { stream = Send("GET", "/v1/" + name + ":watch"); });
  ASSERT_TRUE(testing::WaitUntil(
      [&] { return absl::StrContains(Send("GET", "/metrics"), "\nispq_http_event_streams 1\n"); }));
  const int port = server_->port();
  server_->Stop();
  watcher.join();
  EXPECT_EQ(RawStatus(stream), 200);
  EXPECT_THAT(stream, HasSubstr("id: 0\ndata: "));
  EXPECT_THAT(stream, Not(HasSubstr("event: end")));  // the job goes on
  server_->Stop();
  EXPECT_EQ(RawHttpExchange(port, "GET /healthz HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n"), "");
}

}  // namespace
}  // namespace ispq::server::http
