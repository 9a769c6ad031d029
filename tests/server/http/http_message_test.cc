// SPDX-License-Identifier: Apache-2.0
#include "server/http/http_message.h"

#include <string>

#include "gtest/gtest.h"
#include "server/memory/memory_budget.h"

namespace ispq::server::http {
namespace {

TEST(HttpMessageTest, HeaderIsTheFirstOfItsNameOrEmpty) {
  HttpRequest request;
  request.headers = {{"host", "localhost:8080"},
                     {"authorization", "Bearer first"},
                     {"authorization", "Bearer second"},
                     {"x-empty", ""}};
  EXPECT_EQ(request.Header("authorization"), "Bearer first");
  EXPECT_EQ(request.Header("host"), "localhost:8080");
  EXPECT_EQ(request.Header("x-empty"), "");
  EXPECT_EQ(request.Header("accept"), "");
  EXPECT_EQ(request.Header("authorization").data(), request.headers[1].second.data());  // no copy
}

// A parameter given empty ("?view=") is present: the query parsers refuse it rather than
// falling back to the default.
TEST(HttpMessageTest, ParamIsTheFirstOfItsNameAndHasParamTellsEmptyFromAbsent) {
  HttpRequest request;
  request.query = {{"page_size", "10"}, {"view", ""}, {"page_size", "20"}};
  EXPECT_EQ(request.Param("page_size"), "10");
  EXPECT_TRUE(request.HasParam("view"));
  EXPECT_EQ(request.Param("view"), "");
  EXPECT_FALSE(request.HasParam("state"));
  EXPECT_EQ(request.Param("state"), "");
  // Headers and query parameters are looked up apart.
  EXPECT_FALSE(request.HasParam("host"));
  request.headers = {{"view", "header"}};
  EXPECT_EQ(request.Param("view"), "");
}

TEST(HttpMessageTest, ReleaseBodyFreesTheBodyAndItsShareOfTheBudget) {
  MemoryBudget budget(1 << 20);
  HttpRequest request;
  request.body = std::string(4096, 'x');
  request.body_memory.push_back(budget.ForceReserve(MemoryUse::kRequests, 4096));
  request.body_memory.push_back(budget.ForceReserve(MemoryUse::kRequests, 1024));
  ASSERT_EQ(budget.used(MemoryUse::kRequests), 5120);
  request.ReleaseBody();
  EXPECT_TRUE(request.body.empty());
  EXPECT_EQ(request.body.capacity(), std::string().capacity());  // the bytes are gone too
  EXPECT_TRUE(request.body_memory.empty());
  EXPECT_EQ(budget.used(), 0);
}

}  // namespace
}  // namespace ispq::server::http
