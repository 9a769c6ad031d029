// SPDX-License-Identifier: Apache-2.0
// The helpers every HTTP route answers through: who the caller is (the Authorization header, or
// access_token for an EventSource, which cannot set headers) and the answers as JSON or as a
// mapped error, with a JSON answer held in the memory budget until it has been sent.
#include "server/http/http_exchange.h"

#include <string>

#include "absl/status/status.h"
#include "absl/time/time.h"
#include "google/protobuf/struct.pb.h"
#include "gtest/gtest.h"
#include "server/jobs/retry_hint.h"
#include "tests/server/http/http_test_service.h"

namespace ispq::server::http {
namespace {

HttpRequest WithAuthorization(const std::string& authorization,
                              const std::string& access_token_param = "") {
  HttpRequest request = RouteRequest("GET", "/v1/jobs");
  request.principal = Principal{};
  if (!authorization.empty()) request.headers.emplace_back("authorization", authorization);
  if (!access_token_param.empty()) request.query.emplace_back("access_token", access_token_param);
  return request;
}

std::string Header(const HttpResponse& response, const std::string& name) {
  for (const auto& [key, value] : response.headers) {
    if (key == name) return value;
  }
  return "";
}

v1::Job NamedJob(const std::string& name) {
  v1::Job job;
  job.set_name(name);
  job.set_state(v1::RUNNING);
  job.set_owner("alice");
  return job;
}

class HttpExchangeTest : public ::testing::Test {
 protected:
  HttpTestService service_;
};

TEST_F(HttpExchangeTest, TheCallerIsTheBearerTokensPrincipal) {
  const absl::StatusOr<Principal> alice = AuthenticateRequest(
      WithAuthorization(std::string("Bearer ") + kAliceToken), service_.authenticator);
  ASSERT_TRUE(alice.ok()) << alice.status();
  EXPECT_EQ(alice->name, "alice");
  EXPECT_FALSE(alice->admin);
  const absl::StatusOr<Principal> admin = AuthenticateRequest(
      WithAuthorization(std::string("Bearer ") + kAdminToken), service_.authenticator);
  ASSERT_TRUE(admin.ok()) << admin.status();
  EXPECT_TRUE(admin->admin);

  for (const std::string& refused : {std::string(), std::string("Bearer wrong"),
                                     std::string(kAliceToken), std::string("Basic YWxpY2U=")}) {
    EXPECT_EQ(
        AuthenticateRequest(WithAuthorization(refused), service_.authenticator).status().code(),
        absl::StatusCode::kUnauthenticated)
        << refused;
  }
}

// An EventSource can only send its token in the query; a header, when there is one, wins.
TEST_F(HttpExchangeTest, TheAccessTokenParameterStandsInForAMissingHeader) {
  const absl::StatusOr<Principal> bob =
      AuthenticateRequest(WithAuthorization("", kBobToken), service_.authenticator);
  ASSERT_TRUE(bob.ok()) << bob.status();
  EXPECT_EQ(bob->name, "bob");

  const absl::StatusOr<Principal> header_wins = AuthenticateRequest(
      WithAuthorization(std::string("Bearer ") + kAliceToken, kBobToken), service_.authenticator);
  ASSERT_TRUE(header_wins.ok()) << header_wins.status();
  EXPECT_EQ(header_wins->name, "alice");

  // A wrong header is not rescued by a right parameter.
  EXPECT_FALSE(
      AuthenticateRequest(WithAuthorization("Bearer wrong", kBobToken), service_.authenticator)
          .ok());
  EXPECT_FALSE(AuthenticateRequest(WithAuthorization("", "wrong"), service_.authenticator).ok());
}

TEST_F(HttpExchangeTest, AnErrorIsItsMappedStatusWithTheJsonErrorBody) {
  const HttpResponse missing = ErrorResponse(absl::NotFoundError("jobs/42 \"quoted\""));
  EXPECT_EQ(missing.status, 404);
  EXPECT_EQ(missing.content_type, "application/json");
  const auto body = ParseJson<google::protobuf::Struct>(missing.body);
  EXPECT_EQ(body.fields().at("code").number_value(), 5);
  EXPECT_EQ(body.fields().at("status").string_value(), "NOT_FOUND");
  EXPECT_EQ(body.fields().at("message").string_value(), "jobs/42 \"quoted\"");
  EXPECT_TRUE(missing.headers.empty());
  EXPECT_EQ(missing.memory.bytes(), 0);
}

// A client is told how to authenticate, and when to come back after a refusal with a hint.
TEST_F(HttpExchangeTest, AnErrorCarriesWwwAuthenticateAndRetryAfterWhereTheyApply) {
  const HttpResponse unauthenticated = ErrorResponse(absl::UnauthenticatedError("who are you"));
  EXPECT_EQ(unauthenticated.status, 401);
  EXPECT_EQ(Header(unauthenticated, "WWW-Authenticate"), "Bearer");
  EXPECT_EQ(Header(unauthenticated, "Retry-After"), "");

  const HttpResponse busy =
      ErrorResponse(ResourceExhaustedWithRetryHint("queue full", absl::Milliseconds(2500)));
  EXPECT_EQ(busy.status, 429);
  EXPECT_EQ(Header(busy, "Retry-After"), "3");  // whole seconds, rounded up
  EXPECT_EQ(Header(busy, "WWW-Authenticate"), "");

  const HttpResponse unhinted = ErrorResponse(absl::ResourceExhaustedError("too big"));
  EXPECT_EQ(unhinted.status, 429);
  EXPECT_EQ(Header(unhinted, "Retry-After"), "");
}

TEST_F(HttpExchangeTest, AJsonAnswerIsHeldInTheBudgetUntilItIsLetGo) {
  {
    const HttpResponse answer = JsonResponse(NamedJob("jobs/abc"), service_.memory);
    EXPECT_EQ(answer.status, 200);
    EXPECT_EQ(answer.content_type, "application/json");
    const v1::Job parsed = ParseJson<v1::Job>(answer.body);
    EXPECT_EQ(parsed.name(), "jobs/abc");
    EXPECT_EQ(parsed.state(), v1::RUNNING);
    EXPECT_EQ(service_.budget.used(MemoryUse::kResponses),
              static_cast<int64_t>(answer.body.size()));
    EXPECT_EQ(answer.memory.bytes(), static_cast<int64_t>(answer.body.size()));
  }
  EXPECT_EQ(service_.budget.used(MemoryUse::kResponses), 0);
}

TEST_F(HttpExchangeTest, AJsonAnswerTheBudgetCannotHoldIsRefused) {
  HttpTestService service(/*workers=*/0, /*budget_bytes=*/64);
  const HttpResponse answer = JsonResponse(NamedJob(std::string(200, 'j')), service.memory);
  EXPECT_EQ(answer.status, 429);
  EXPECT_EQ(ParseJson<google::protobuf::Struct>(answer.body).fields().at("status").string_value(),
            "RESOURCE_EXHAUSTED");
  EXPECT_EQ(service.budget.used(), 0);
}

TEST_F(HttpExchangeTest, ReplyAnswersTheValueOrTheError) {
  const HttpResponse found =
      Reply(absl::StatusOr<v1::Job>(NamedJob("jobs/found")), service_.memory);
  EXPECT_EQ(found.status, 200);
  EXPECT_EQ(ParseJson<v1::Job>(found.body).name(), "jobs/found");
  const HttpResponse refused =
      Reply(absl::StatusOr<v1::Job>(absl::InvalidArgumentError("bad view")), service_.memory);
  EXPECT_EQ(refused.status, 400);
  EXPECT_EQ(ParseJson<google::protobuf::Struct>(refused.body).fields().at("message").string_value(),
            "bad view");
}

}  // namespace
}  // namespace ispq::server::http
