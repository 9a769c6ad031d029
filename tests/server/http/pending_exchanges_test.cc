// SPDX-License-Identifier: Apache-2.0
#include "server/http/pending_exchanges.h"

#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "absl/time/clock.h"
#include "absl/time/time.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "server/http/http_router.h"
#include "server/http/request_body.h"
#include "server/http/request_exchange.h"
#include "server/http/suspensions.h"
#include "server/jobs/job_scheduler.h"
#include "server/store/mesh_store.h"

namespace ispq::server::http {
namespace {

using ::testing::HasSubstr;

// Exchanges that are never suspended, so that no libmicrohttpd connection is needed: the set
// and its answers are what is tested, not the suspension (server/http/request_exchange.h).
class PendingExchangesTest : public ::testing::Test {
 protected:
  PendingExchangesTest()
      : budget_(1 << 20),
        meshes_(10),
        scheduler_({.workers = 1, .max_queued_jobs = 10, .retention = {}}, metrics_, &budget_),
        memory_(budget_, scheduler_, meshes_, metrics_) {
    route_.timeout_message = "the submission took too long; retry it with its requestId";
  }

  std::shared_ptr<RequestExchange> NewExchange(absl::Time deadline) {
    auto exchange =
        std::make_shared<RequestExchange>(nullptr, RequestBody(memory_, 1024), suspensions_);
    exchange->route = &route_;
    exchange->deadline = deadline;
    return exchange;
  }

  ServerMetrics metrics_;
  MemoryBudget budget_;
  InMemoryMeshStore meshes_;
  JobScheduler scheduler_;
  MemoryAdmission memory_;
  Suspensions suspensions_;
  Route route_;
};

TEST_F(PendingExchangesTest, ExpireAnswersOnlyThoseLateWith504AndTheRoutesMessage) {
  PendingExchanges pending;
  const absl::Time now = absl::Now();
  const auto late = NewExchange(now - absl::Seconds(1));
  const auto due_now = NewExchange(now);
  const auto on_time = NewExchange(now + absl::Seconds(1));
  ASSERT_TRUE(pending.Add(late));
  ASSERT_TRUE(pending.Add(due_now));
  ASSERT_TRUE(pending.Add(on_time));
  EXPECT_EQ(pending.size(), 3);

  pending.Expire(now);
  for (const auto& exchange : {late, due_now}) {
    ASSERT_TRUE(exchange->Answered());
    const std::optional<HttpResponse> answer = exchange->TakeAnswer();
    ASSERT_TRUE(answer.has_value());
    EXPECT_EQ(answer->status, 504);
    EXPECT_THAT(answer->body, HasSubstr("DEADLINE_EXCEEDED"));
    EXPECT_THAT(answer->body, HasSubstr(route_.timeout_message));
  }
  EXPECT_FALSE(on_time->Answered());
  EXPECT_EQ(pending.size(), 1);  // the answered ones left the set
}

// The route's own answer takes the exchange out; a later Expire does not touch it.
TEST_F(PendingExchangesTest, AnExchangeAnsweredByItsRouteLeavesTheSet) {
  PendingExchanges pending;
  const auto exchange = NewExchange(absl::Now() + absl::Hours(1));
  ASSERT_TRUE(pending.Add(exchange));
  HttpResponse ok;
  ok.body = "{}";
  exchange->Answer(std::move(ok));
  EXPECT_EQ(pending.size(), 0);
  pending.Expire(absl::Now() + absl::Hours(2));
  const std::optional<HttpResponse> answer = exchange->TakeAnswer();
  ASSERT_TRUE(answer.has_value());
  EXPECT_EQ(answer->status, 200);
  EXPECT_EQ(exchange.use_count(), 1);  // the set holds no reference any more
}

// A route on another thread may answer before Add has registered its callback.
TEST_F(PendingExchangesTest, AnExchangeAnsweredBeforeItWasAddedDoesNotStay) {
  PendingExchanges pending;
  const auto exchange = NewExchange(absl::Now() + absl::Hours(1));
  exchange->Answer(HttpResponse());
  ASSERT_TRUE(pending.Add(exchange));
  EXPECT_EQ(pending.size(), 0);
}

// At shutdown no connection may stay suspended: every pending exchange is answered 503, and one
// that arrives after is refused so that its caller answers it.
TEST_F(PendingExchangesTest, StopAllAnswersEveryOneWith503AndRefusesNewOnes) {
  PendingExchanges pending;
  std::vector<std::shared_ptr<RequestExchange>> exchanges;
  for (int i = 0; i < 3; ++i) {
    exchanges.push_back(NewExchange(absl::Now() + absl::Hours(1)));
    ASSERT_TRUE(pending.Add(exchanges.back()));
  }
  pending.StopAll();
  EXPECT_EQ(pending.size(), 0);
  for (const auto& exchange : exchanges) {
    const std::optional<HttpResponse> answer = exchange->TakeAnswer();
    ASSERT_TRUE(answer.has_value());
    EXPECT_EQ(answer->status, 503);
    EXPECT_THAT(answer->body, HasSubstr("shutting down"));
  }
  const auto late = NewExchange(absl::Now() + absl::Hours(1));
  EXPECT_FALSE(pending.Add(late));
  EXPECT_FALSE(late->Answered());
  EXPECT_EQ(pending.size(), 0);
}

// Routes answering on their threads while the server expires and stops: every exchange gets
// exactly one answer and the set ends empty.
TEST_F(PendingExchangesTest, RoutesAnsweringConcurrentlyWithExpireAndStop) {
  PendingExchanges pending;
  constexpr int kExchanges = 200;
  const absl::Time now = absl::Now();
  std::vector<std::shared_ptr<RequestExchange>> exchanges;
  for (int i = 0; i < kExchanges; ++i) {
    exchanges.push_back(NewExchange(i % 2 == 0 ? now : now + absl::Hours(1)));
    ASSERT_TRUE(pending.Add(exchanges.back()));
  }
  std::thread routes([&] {
    for (int i = kExchanges - 1; i >= 0; --i) exchanges[i]->Answer(HttpResponse());
  });
  pending.Expire(now);
  pending.StopAll();
  routes.join();
  EXPECT_EQ(pending.size(), 0);
  for (const auto& exchange : exchanges) {
    ASSERT_TRUE(exchange->TakeAnswer().has_value());
    EXPECT_FALSE(exchange->TakeAnswer().has_value());
  }
}

}  // namespace
}  // namespace ispq::server::http
