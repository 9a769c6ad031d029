// SPDX-License-Identifier: Apache-2.0
// What the event thread does with each request, on a real libmicrohttpd daemon on loopback set
// up as the server sets it up, with routes of the test's own: the head's checks come in their
// documented order and refuse before any body is read or any route runs (each refusal counted);
// a body is taken whole within its limit and the budget, or refused midway; a route answers on
// the event thread or, with its connection suspended, from its pool; the server answers for a
// route that takes too long, and refuses everything once it stops. The checks themselves
// (framing, Host and Origin, authentication) have tests of their own.
#include "server/http/request_dispatcher.h"

#include <arpa/inet.h>
#include <microhttpd.h>
#include <netinet/in.h>

#include <atomic>
#include <memory>
#include <string>
#include <thread>
#include <utility>

#include "absl/base/thread_annotations.h"
#include "absl/strings/ascii.h"
#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"
#include "absl/synchronization/mutex.h"
#include "absl/time/clock.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "server/http/connection_deadlines.h"
#include "server/http/handler_pool.h"
#include "server/http/http_refusals.h"
#include "server/http/mhd_callbacks.h"
#include "server/http/origin_policy.h"
#include "server/http/pending_exchanges.h"
#include "server/http/suspensions.h"
#include "tests/server/http/http_test_service.h"
#include "tests/support/bounded_wait.h"

namespace ispq::server::http {
namespace {

using ::testing::HasSubstr;

constexpr int64_t kMaxBody = 1000;
constexpr char kSlowRouteMessage[] = "the slow route gave up";

HttpResponse Text(std::string body) {
  HttpResponse response;
  response.content_type = "text/plain";
  response.body = std::move(body);
  return response;
}

std::string BodyOf(const std::string& answer) {
  const size_t head_end = answer.find("\r\n\r\n");
  return head_end == std::string::npos ? "" : answer.substr(head_end + 4);
}

class RequestDispatcherTest : public ::testing::Test {
 protected:
  // Serves the test's routes on 127.0.0.1 port 0 with a memory budget of `budget_bytes`.
  void Start(int64_t budget_bytes = int64_t{1} << 30) {
    service_ = std::make_unique<HttpTestService>(/*workers=*/0, budget_bytes);
    parts_ = std::make_unique<HttpParts>(service_->parts());
    limits_.max_body_bytes = kMaxBody;
    limits_.allowed_hosts = {"127.0.0.1"};
    AddRoutes();
    origins_ = std::make_unique<OriginPolicy>(limits_.allowed_hosts, "127.0.0.1", 0);
    dispatcher_ = std::make_unique<RequestDispatcher>(DispatcherParts{
        .parts = *parts_,
        .limits = limits_,
        .router = router_,
        .origins = *origins_,
        .lanes = {.operator_lane = &operator_pool_, .lookup = &lookup_pool_, .parse = &parse_pool_},
        .pending = pending_,
        .deadlines = deadlines_,
        .suspensions = suspensions_,
        .refusals = refusals_});
    sockaddr_in address = {};
    address.sin_family = AF_INET;
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    daemon_ = MHD_start_daemon(
        MHD_USE_EPOLL_INTERNAL_THREAD | MHD_ALLOW_SUSPEND_RESUME, 0, nullptr, nullptr,
        &OnMhdRequest, dispatcher_.get(), MHD_OPTION_SOCK_ADDR,
        reinterpret_cast<sockaddr*>(&address), MHD_OPTION_CONNECTION_MEMORY_LIMIT, size_t{64 << 10},
        MHD_OPTION_NOTIFY_COMPLETED, &OnMhdRequestCompleted, dispatcher_.get(),
        MHD_OPTION_NOTIFY_CONNECTION, &OnMhdConnection, &deadlines_, MHD_OPTION_END);
    ASSERT_NE(daemon_, nullptr);
    port_ = MHD_get_daemon_info(daemon_, MHD_DAEMON_INFO_BIND_PORT)->port;
    ASSERT_GT(port_, 0);
  }

  ~RequestDispatcherTest() override {
    if (daemon_ != nullptr) {
      // libmicrohttpd cannot stop with a suspended connection: answer whatever still waits.
      pending_.StopAll();
      EXPECT_TRUE(testing::WaitUntil([this] { return suspensions_.suspended() == 0; }));
      MHD_stop_daemon(daemon_);
    }
    operator_pool_.Stop();
    lookup_pool_.Stop();
    parse_pool_.Stop();
  }

  void AddRoutes() {
    Route inline_route = Named("GET", "/inline", Lane::kInline);
    inline_route.handle = [](HttpRequest&, const std::shared_ptr<Responder>& responder) {
      responder->Answer(Text("inline"));
    };
    router_.Add(std::move(inline_route));

    Route pooled = Named("GET", "/pooled", Lane::kLookup);
    pooled.handle = [this](HttpRequest&, const std::shared_ptr<Responder>& responder) {
      pooled_thread_ = std::this_thread::get_id();
      responder->Answer(Text("pooled"));
    };
    router_.Add(std::move(pooled));

    Route echo = Named("POST", "/echo", Lane::kParse);
    echo.takes_body = true;
    echo.authenticated = true;
    echo.handle = [this](HttpRequest& request, const std::shared_ptr<Responder>& responder) {
      echoes_.fetch_add(1);
      responder->Answer(Text(absl::StrCat(request.principal.name, ":", request.body)));
    };
    router_.Add(std::move(echo));

    Route private_route = Named("GET", "/private", Lane::kInline);
    private_route.authenticated = true;
    private_route.handle = [](HttpRequest& request, const std::shared_ptr<Responder>& responder) {
      responder->Answer(Text(request.principal.name));
    };
    router_.Add(std::move(private_route));

    Route probe = Named("GET", "/probe", Lane::kInline);
    probe.any_host = true;
    probe.handle = [](HttpRequest&, const std::shared_ptr<Responder>& responder) {
      responder->Answer(Text("probe"));
    };
    router_.Add(std::move(probe));

    Route slow = Named("GET", "/slow", Lane::kLookup);
    slow.timeout_message = kSlowRouteMessage;
    slow.handle = [this](HttpRequest&, const std::shared_ptr<Responder>& responder) {
      absl::MutexLock lock(&mutex_);
      slow_responder_ = responder;  // answered only when the test says so
    };
    router_.Add(std::move(slow));

    Route silent = Named("GET", "/silent", Lane::kInline);
    silent.handle = [](HttpRequest&, const std::shared_ptr<Responder>&) {};
    router_.Add(std::move(silent));
  }

  static Route Named(const char* method, const char* pattern, Lane lane) {
    Route route;
    route.method = method;
    route.pattern = pattern;
    route.lane = lane;
    return route;
  }

  // A request with `Connection: close` and, unless `headers` has one, Host 127.0.0.1:port.
  std::string Request(const std::string& method, const std::string& path,
                      const std::string& headers = "", const std::string& body = "") const {
    std::string request = absl::StrCat(method, " ", path, " HTTP/1.1\r\nConnection: close\r\n");
    if (!absl::StrContains(absl::AsciiStrToLower(headers), "host:")) {
      absl::StrAppend(&request, "Host: 127.0.0.1:", port_, "\r\n");
    }
    return absl::StrCat(request, headers, "\r\n", body);
  }

  std::string Exchange(const std::string& request) { return RawHttpExchange(port_, request); }

  // A JSON POST to /echo with `body` and, if set, alice's token.
  std::string EchoRequest(const std::string& body, bool with_token,
                          const std::string& more_headers = "") const {
    std::string headers = absl::StrCat(
        "Content-Type: application/json\r\nContent-Length: ", body.size(), "\r\n", more_headers);
    if (with_token) absl::StrAppend(&headers, "Authorization: Bearer ", kAliceToken, "\r\n");
    return Request("POST", "/echo", headers, body);
  }

  int64_t Refused(int status) const {
    const auto counts = refusals_.ByStatus();
    const auto found = counts.find(status);
    return found == counts.end() ? 0 : found->second;
  }

  std::shared_ptr<Responder> SlowResponder() {
    absl::MutexLock lock(&mutex_);
    return slow_responder_;
  }

  std::unique_ptr<HttpTestService> service_;
  std::unique_ptr<HttpParts> parts_;
  HttpLimits limits_;
  Router router_;
  std::unique_ptr<OriginPolicy> origins_;
  HandlerPool operator_pool_{1, "test-ops"};
  HandlerPool lookup_pool_{2, "test-look"};
  HandlerPool parse_pool_{1, "test-parse"};
  PendingExchanges pending_;
  ConnectionDeadlines deadlines_{absl::Seconds(60), absl::Seconds(60)};
  Suspensions suspensions_;
  HttpRefusals refusals_;
  std::unique_ptr<RequestDispatcher> dispatcher_;
  MHD_Daemon* daemon_ = nullptr;
  int port_ = 0;

  std::atomic<int> echoes_{0};
  std::atomic<std::thread::id> pooled_thread_{};
  absl::Mutex mutex_;
  std::shared_ptr<Responder> slow_responder_ ABSL_GUARDED_BY(mutex_);
};

TEST_F(RequestDispatcherTest, RoutesAnswerOnTheEventThreadOrFromTheirPool) {
  Start();
  const std::string inline_answer = Exchange(Request("GET", "/inline"));
  EXPECT_EQ(RawStatus(inline_answer), 200) << inline_answer;
  EXPECT_EQ(BodyOf(inline_answer), "inline");

  const std::string pooled = Exchange(Request("GET", "/pooled"));
  EXPECT_EQ(RawStatus(pooled), 200) << pooled;
  EXPECT_EQ(BodyOf(pooled), "pooled");
  EXPECT_NE(pooled_thread_.load(), std::this_thread::get_id());
  // The connection was suspended while the pool answered, and resumed for the answer.
  EXPECT_TRUE(testing::WaitUntil([this] { return suspensions_.suspended() == 0; }));
  EXPECT_EQ(pending_.size(), 0);

  // HEAD is served by the GET route, without the body.
  const std::string head = Exchange(Request("HEAD", "/inline"));
  EXPECT_EQ(RawStatus(head), 200) << head;
  EXPECT_EQ(BodyOf(head), "");
}

// Each check answers before the later ones run: a request from another site is refused for its
// Host or Origin whatever else it gets wrong, and no route runs for a refused request.
TEST_F(RequestDispatcherTest, TheHeadIsCheckedInOrderBeforeAnyRouteRuns) {
  Start();
  const std::string evil_host = "Host: evil.example\r\n";
  EXPECT_EQ(RawStatus(Exchange(Request("GET", "/nowhere", evil_host))), 421);
  EXPECT_EQ(RawStatus(Exchange(Request("GET", "/private", evil_host))), 421);
  EXPECT_EQ(RawStatus(Exchange(Request("GET", "/probe", evil_host))), 200);  // any Host
  EXPECT_EQ(RawStatus(Exchange(Request("GET", "/nowhere"))), 404);

  // The Content-Type before the Origin before the caller.
  EXPECT_EQ(RawStatus(Exchange(Request(
                "POST", "/echo",
                "Content-Type: text/plain\r\nOrigin: http://evil.example\r\nContent-Length: 2\r\n",
                "{}"))),
            415);
  EXPECT_EQ(RawStatus(Exchange(EchoRequest("{}", false, "Origin: http://evil.example\r\n"))), 403);
  const std::string unauthenticated = Exchange(EchoRequest("{}", false));
  EXPECT_EQ(RawStatus(unauthenticated), 401) << unauthenticated;
  EXPECT_THAT(unauthenticated, HasSubstr("WWW-Authenticate: Bearer"));
  EXPECT_THAT(BodyOf(unauthenticated), HasSubstr("UNAUTHENTICATED"));
  EXPECT_EQ(RawStatus(Exchange(Request("GET", "/private"))), 401);
  // The length before the caller: a body too long is refused from its head, unread.
  EXPECT_EQ(
      RawStatus(Exchange(Request("POST", "/echo",
                                 absl::StrCat("Content-Type: application/json\r\nContent-Length: ",
                                              kMaxBody + 1, "\r\n")))),
      413);
  EXPECT_EQ(echoes_.load(), 0);

  EXPECT_EQ(Refused(421), 2);
  EXPECT_EQ(Refused(404), 1);
  EXPECT_EQ(Refused(415), 1);
  EXPECT_EQ(Refused(403), 1);
  EXPECT_EQ(Refused(401), 2);
  EXPECT_EQ(Refused(413), 1);
  EXPECT_EQ(Refused(200), 0);

  const std::string privately = Exchange(
      Request("GET", "/private", absl::StrCat("Authorization: Bearer ", kBobToken, "\r\n")));
  EXPECT_EQ(RawStatus(privately), 200) << privately;
  EXPECT_EQ(BodyOf(privately), "bob");  // the caller the head named is the route's principal
}

TEST_F(RequestDispatcherTest, TheRouteGetsTheWholeBodyAndItsCaller) {
  Start();
  const std::string body = absl::StrCat("{\"text\": \"", std::string(600, 'x'), "\"}");
  const std::string answer = Exchange(EchoRequest(body, true));
  EXPECT_EQ(RawStatus(answer), 200) << answer;
  EXPECT_EQ(BodyOf(answer), absl::StrCat("alice:", body));

  // In chunks, as it arrives.
  const std::string chunked = Exchange(
      Request("POST", "/echo",
              absl::StrCat("Content-Type: application/json\r\nTransfer-Encoding: chunked\r\n",
                           "Authorization: Bearer ", kAliceToken, "\r\n"),
              "3\r\n{\"a\r\n5\r\n\": 12\r\n1\r\n}\r\n0\r\n\r\n"));
  EXPECT_EQ(RawStatus(chunked), 200) << chunked;
  EXPECT_EQ(BodyOf(chunked), "alice:{\"a\": 12}");
  EXPECT_EQ(echoes_.load(), 2);
  // The bodies' share of the budget is given back with the requests.
  EXPECT_TRUE(testing::WaitUntil([this] { return service_->budget.used() == 0; }));
}

// A chunked body says nothing of its length up front: it is refused as it passes the limit, with
// the refusal written ahead of the close.
TEST_F(RequestDispatcherTest, AChunkedBodyPastTheLimitIsRefusedMidway) {
  Start();
  std::string chunks;
  for (int i = 0; i < 3; ++i) absl::StrAppend(&chunks, "190\r\n", std::string(400, ' '), "\r\n");
  const std::string answer = Exchange(
      Request("POST", "/echo",
              absl::StrCat("Content-Type: application/json\r\nTransfer-Encoding: chunked\r\n",
                           "Authorization: Bearer ", kAliceToken, "\r\n"),
              absl::StrCat(chunks, "0\r\n\r\n")));
  EXPECT_EQ(RawStatus(answer), 413) << answer;
  EXPECT_THAT(BodyOf(answer), HasSubstr("RESOURCE_EXHAUSTED"));
  EXPECT_EQ(echoes_.load(), 0);
  EXPECT_EQ(Refused(413), 1);
  EXPECT_TRUE(testing::WaitUntil([this] { return service_->budget.used() == 0; }));
}

TEST_F(RequestDispatcherTest, ADeclaredLengthTheBudgetCannotHoldIsRefusedUnread) {
  Start(/*budget_bytes=*/500);
  const std::string answer =
      Exchange(Request("POST", "/echo",
                       absl::StrCat("Content-Type: application/json\r\nContent-Length: 800\r\n",
                                    "Authorization: Bearer ", kAliceToken, "\r\n")));
  EXPECT_EQ(RawStatus(answer), 429) << answer;
  EXPECT_EQ(echoes_.load(), 0);
  EXPECT_EQ(Refused(429), 1);
  EXPECT_EQ(service_->budget.used(), 0);
  // A body the budget holds still goes through.
  EXPECT_EQ(RawStatus(Exchange(EchoRequest("{}", true))), 200);
}

// The route's work is abandoned: the client gets 504 with the route's message, and the route's
// late answer is ignored.
TEST_F(RequestDispatcherTest, ARouteThatTakesTooLongIsAnsweredForWithItsTimeoutMessage) {
  Start();
  std::string answer;
  std::thread client([&] { answer = Exchange(Request("GET", "/slow")); });
  ASSERT_TRUE(testing::WaitUntil([this] { return SlowResponder() != nullptr; }));
  EXPECT_EQ(pending_.size(), 1);
  EXPECT_EQ(suspensions_.suspended(), 1);
  pending_.Expire(absl::Now());  // its deadline (answer_timeout) has not passed: nothing
  EXPECT_FALSE(SlowResponder()->Answered());
  pending_.Expire(absl::Now() + limits_.answer_timeout + absl::Seconds(1));
  client.join();
  EXPECT_EQ(RawStatus(answer), 504) << answer;
  EXPECT_THAT(BodyOf(answer), HasSubstr(kSlowRouteMessage));
  EXPECT_TRUE(SlowResponder()->Answered());
  SlowResponder()->Answer(Text("too late"));
  EXPECT_EQ(pending_.size(), 0);
  EXPECT_TRUE(testing::WaitUntil([this] { return suspensions_.suspended() == 0; }));
}

// Shutdown: waiting requests are answered 503 (libmicrohttpd cannot stop with one suspended)
// and new ones, probes included, are refused.
TEST_F(RequestDispatcherTest, OnceStoppingEveryRequestIsRefusedWith503) {
  Start();
  std::string waiting;
  std::thread client([&] { waiting = Exchange(Request("GET", "/slow")); });
  ASSERT_TRUE(testing::WaitUntil([this] { return SlowResponder() != nullptr; }));
  dispatcher_->StopAccepting();
  for (const char* path : {"/inline", "/probe", "/pooled", "/nowhere"}) {
    const std::string refused = Exchange(Request("GET", path));
    EXPECT_EQ(RawStatus(refused), 503) << path << ": " << refused;
    EXPECT_THAT(BodyOf(refused), HasSubstr("shutting down")) << path;
  }
  pending_.StopAll();
  client.join();
  EXPECT_EQ(RawStatus(waiting), 503) << waiting;
  EXPECT_EQ(Refused(503), 4);
}

TEST_F(RequestDispatcherTest, ARouteThatDoesNotAnswerClosesTheConnection) {
  Start();
  EXPECT_EQ(Exchange(Request("GET", "/silent")), "");
  EXPECT_EQ(RawStatus(Exchange(Request("GET", "/inline"))), 200);  // the server carries on
}

}  // namespace
}  // namespace ispq::server::http
