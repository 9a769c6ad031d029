// SPDX-License-Identifier: Apache-2.0
// One request from its head to its answer: only the first answer counts (a route answering after
// the server answered for it on a timeout or at shutdown is ignored), the answer is kept for the
// event thread to take once, and whoever waits for it (the pending set) hears of it once. The
// suspension of a live connection is exercised with a real daemon in
// request_dispatcher_test.cc.
#include "server/http/request_exchange.h"

#include <atomic>
#include <memory>
#include <optional>
#include <thread>
#include <vector>

#include "gtest/gtest.h"
#include "tests/server/http/http_test_service.h"

namespace ispq::server::http {
namespace {

HttpResponse WithStatus(int status) {
  HttpResponse response;
  response.status = status;
  return response;
}

class RequestExchangeTest : public ::testing::Test {
 protected:
  std::shared_ptr<RequestExchange> NewExchange() {
    // No connection: nothing here may suspend or resume one.
    return std::make_shared<RequestExchange>(nullptr, RequestBody(service_.memory, 1 << 10),
                                             suspensions_);
  }

  HttpTestService service_;
  Suspensions suspensions_;
};

TEST_F(RequestExchangeTest, OnlyTheFirstAnswerCountsAndIsTakenOnce) {
  const std::shared_ptr<RequestExchange> exchange = NewExchange();
  EXPECT_FALSE(exchange->Answered());
  EXPECT_FALSE(exchange->TakeAnswer().has_value());
  exchange->Answer(WithStatus(200));
  EXPECT_TRUE(exchange->Answered());
  exchange->Answer(WithStatus(504));  // the server's timeout, after the route's answer
  std::optional<HttpResponse> answer = exchange->TakeAnswer();
  ASSERT_TRUE(answer.has_value());
  EXPECT_EQ(answer->status, 200);
  EXPECT_FALSE(exchange->TakeAnswer().has_value());
  // Taken, it stays answered: a late route still sees it should stop.
  EXPECT_TRUE(exchange->Answered());
  exchange->Answer(WithStatus(500));
  EXPECT_FALSE(exchange->TakeAnswer().has_value());
}

// The pending set learns of the answer (to let go of the exchange) once, with the answer kept.
TEST_F(RequestExchangeTest, OnAnswerRunsOnceAfterTheAnswerIsKept) {
  const std::shared_ptr<RequestExchange> exchange = NewExchange();
  int calls = 0;
  bool answered_when_called = false;
  exchange->OnAnswer([&] {
    ++calls;
    answered_when_called = exchange->Answered();
  });
  EXPECT_EQ(calls, 0);
  exchange->Answer(WithStatus(200));
  exchange->Answer(WithStatus(503));
  EXPECT_EQ(calls, 1);
  EXPECT_TRUE(answered_when_called);
}

// An inline route (or a refusal while dispatching) answers before the dispatcher would suspend:
// the connection must then not be suspended, or it would wait for a resume that never comes.
TEST_F(RequestExchangeTest, SuspendAfterTheAnswerLeavesTheConnectionAlone) {
  const std::shared_ptr<RequestExchange> exchange = NewExchange();
  exchange->Answer(WithStatus(200));
  exchange->Suspend();  // would suspend a null connection if it did anything
  EXPECT_EQ(suspensions_.suspended(), 0);
  EXPECT_TRUE(exchange->TakeAnswer().has_value());
}

// The route's thread, the timeout and the shutdown may answer at once: one answer wins.
TEST_F(RequestExchangeTest, ConcurrentAnswersKeepExactlyOne) {
  const std::shared_ptr<RequestExchange> exchange = NewExchange();
  std::atomic<int> calls{0};
  exchange->OnAnswer([&] { calls.fetch_add(1); });
  std::vector<std::thread> answering;
  for (int status : {200, 503, 504, 500}) {
    answering.emplace_back([exchange, status] { exchange->Answer(WithStatus(status)); });
  }
  for (std::thread& thread : answering) thread.join();
  EXPECT_EQ(calls.load(), 1);
  std::optional<HttpResponse> answer = exchange->TakeAnswer();
  ASSERT_TRUE(answer.has_value());
  EXPECT_TRUE(answer->status == 200 || answer->status == 503 || answer->status == 504 ||
              answer->status == 500)
      << answer->status;
  EXPECT_FALSE(exchange->TakeAnswer().has_value());
}

}  // namespace
}  // namespace ispq::server::http
