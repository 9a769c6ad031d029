// SPDX-License-Identifier: Apache-2.0
#include "server/http/http_router.h"

#include <string>

#include "gtest/gtest.h"

namespace ispq::server::http {
namespace {

Route Named(const char* method, const char* pattern) {
  Route route;
  route.method = method;
  route.pattern = pattern;
  return route;
}

TEST(HttpRouterTest, MatchesPathsAndTheIdSegment) {
  Router router;
  router.Add(Named("GET", "/v1/jobs"));
  router.Add(Named("GET", "/v1/jobs/{id}"));
  router.Add(Named("POST", "/v1/jobs/{id}:cancel"));
  router.Add(Named("GET", "/v1/jobs/{id}:watch"));
  std::string id;
  const Route* route = router.Match("GET", "/v1/jobs", &id);
  ASSERT_NE(route, nullptr);
  EXPECT_EQ(route->pattern, "/v1/jobs");
  route = router.Match("GET", "/v1/jobs/abc123", &id);
  ASSERT_NE(route, nullptr);
  EXPECT_EQ(route->pattern, "/v1/jobs/{id}");
  EXPECT_EQ(id, "abc123");
  route = router.Match("HEAD", "/v1/jobs/x:watch", &id);  // HEAD is served as GET
  ASSERT_NE(route, nullptr);
  EXPECT_EQ(route->pattern, "/v1/jobs/{id}:watch");
  EXPECT_EQ(id, "x");
  route = router.Match("POST", "/v1/jobs/y:cancel", &id);
  ASSERT_NE(route, nullptr);
  EXPECT_EQ(id, "y");

  EXPECT_EQ(router.Match("GET", "/v1/jobs/y:cancel", &id), nullptr);  // wrong method
  EXPECT_EQ(router.Match("POST", "/v1/jobs", &id), nullptr);
  EXPECT_EQ(router.Match("GET", "/v1/jobs/", &id), nullptr);  // an empty id
  EXPECT_EQ(router.Match("GET", "/v1/jobs/a/b", &id), nullptr);
  EXPECT_EQ(router.Match("GET", "/v1/jobs/a:b:watch", &id), nullptr);
  EXPECT_EQ(router.Match("DELETE", "/v1/jobs/a", &id), nullptr);
  EXPECT_EQ(router.Match("GET", "/v1/jobsx", &id), nullptr);
}

}  // namespace
}  // namespace ispq::server::http
