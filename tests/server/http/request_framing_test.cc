// SPDX-License-Identifier: Apache-2.0
#include "server/http/request_framing.h"

#include <string>

#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "server/http/http_status.h"

namespace ispq::server::http {
namespace {

using ::testing::HasSubstr;

HttpRequest Post(HttpFields headers) {
  HttpRequest request;
  request.method = "POST";
  request.path = "/v1/jobs";
  request.headers = std::move(headers);
  return request;
}

int HttpStatusOfPlan(const HttpRequest& request, int64_t max = 1000) {
  const absl::StatusOr<BodyFraming> framing = PlanBody(request, max);
  return framing.ok() ? 200 : HttpStatusOf(framing.status());
}

TEST(RequestFramingTest, BoundsTheHead) {
  const HttpLimits limits;
  EXPECT_TRUE(
      CheckHeadSize({.target_bytes = 8192, .header_bytes = 32768, .header_count = 100}, limits)
          .ok());
  EXPECT_EQ(HttpStatusOf(CheckHeadSize({.target_bytes = 8193, .header_bytes = 0, .header_count = 0},
                                       limits)),
            414);
  EXPECT_EQ(HttpStatusOf(CheckHeadSize(
                {.target_bytes = 10, .header_bytes = 32769, .header_count = 1}, limits)),
            431);
  EXPECT_EQ(HttpStatusOf(CheckHeadSize(
                {.target_bytes = 10, .header_bytes = 100, .header_count = 101}, limits)),
            431);
}

TEST(RequestFramingTest, PlansTheBody) {
  absl::StatusOr<BodyFraming> framing = PlanBody(Post({{"content-length", "12"}}), 1000);
  ASSERT_TRUE(framing.ok());
  EXPECT_FALSE(framing->chunked);
  EXPECT_EQ(framing->length, 12);
  framing = PlanBody(Post({{"transfer-encoding", "Chunked"}}), 1000);
  ASSERT_TRUE(framing.ok());
  EXPECT_TRUE(framing->chunked);
  HttpRequest get;
  get.method = "GET";
  EXPECT_TRUE(PlanBody(get, 1000).ok());
  EXPECT_EQ(HttpStatusOfPlan(Post({{"content-length", "0"}, {"content-encoding", "identity"}})),
            200);
}

TEST(RequestFramingTest, RefusesBodiesItWouldHaveToDecodeOrCannotBound) {
  EXPECT_EQ(HttpStatusOfPlan(Post({})), 411);
  EXPECT_EQ(HttpStatusOfPlan(Post({{"content-length", "1001"}})), 413);
  EXPECT_EQ(HttpStatusOfPlan(Post({{"content-length", "10"}, {"content-encoding", "gzip"}})), 415);
  EXPECT_EQ(
      HttpStatusOfPlan(Post({{"content-length", "10"}, {"content-encoding", "identity, deflate"}})),
      415);
  EXPECT_EQ(HttpStatusOfPlan(Post({{"transfer-encoding", "gzip, chunked"}})), 501);
  EXPECT_EQ(HttpStatusOfPlan(Post({{"transfer-encoding", "chunked"}, {"content-length", "3"}})),
            400);
  EXPECT_EQ(HttpStatusOfPlan(Post({{"content-length", "3"}, {"content-length", "4"}})), 400);
  EXPECT_EQ(HttpStatusOfPlan(Post({{"content-length", "-3"}})), 400);
  EXPECT_EQ(HttpStatusOfPlan(Post({{"content-length", "0x10"}})), 400);
}

TEST(RequestFramingTest, TakesOnlyJson) {
  for (const char* json :
       {"application/json", "Application/JSON", "application/json; charset=utf-8",
        "application/json;charset=\"UTF-8\""}) {
    EXPECT_TRUE(CheckJsonContentType(Post({{"content-type", json}})).ok()) << json;
  }
  for (const char* other : {"text/plain", "application/xml", "image/png",
                            "application/x-www-form-urlencoded", "multipart/form-data; boundary=x",
                            "application/json; charset=latin1", "application/jsonx"}) {
    const absl::Status refused = CheckJsonContentType(Post({{"content-type", other}}));
    EXPECT_EQ(HttpStatusOf(refused), 415) << other;
  }
  EXPECT_THAT(CheckJsonContentType(Post({})).message(), HasSubstr("missing"));
  EXPECT_EQ(HttpStatusOf(CheckJsonContentType(
                Post({{"content-type", "application/json"}, {"content-type", "text/plain"}}))),
            415);
}

TEST(RequestFramingTest, ProtobufIsAcceptedOnlyWhereTheRouteTakesIt) {
  const HttpRequest protobuf = Post({{"content-type", "application/x-protobuf"}});
  EXPECT_EQ(HttpStatusOf(CheckJsonContentType(protobuf)), 415);
  EXPECT_TRUE(CheckJsonContentType(protobuf, /*protobuf_too=*/true).ok());
  EXPECT_TRUE(IsProtobufBody(protobuf));
  EXPECT_FALSE(IsProtobufBody(Post({{"content-type", "application/json"}})));
  // Still nothing a cross-site form can send without asking first.
  for (const char* other : {"text/plain", "application/x-www-form-urlencoded",
                            "application/x-protobuf; charset=utf-8", "application/octet-stream"}) {
    const absl::Status refused = CheckJsonContentType(Post({{"content-type", other}}), true);
    EXPECT_EQ(HttpStatusOf(refused), 415) << other;
    EXPECT_THAT(refused.message(), HasSubstr("application/x-protobuf")) << other;
  }
}

}  // namespace
}  // namespace ispq::server::http
