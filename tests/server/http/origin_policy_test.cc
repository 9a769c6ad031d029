// SPDX-License-Identifier: Apache-2.0
#include "server/http/origin_policy.h"

#include <string>

#include "gtest/gtest.h"
#include "server/http/http_status.h"

namespace ispq::server::http {
namespace {

HttpRequest Request(const std::string& method, HttpFields headers) {
  HttpRequest request;
  request.method = method;
  request.path = "/v1/jobs";
  request.headers = std::move(headers);
  return request;
}

int HostStatus(const OriginPolicy& policy, const std::string& host) {
  const absl::Status checked = policy.CheckHost(Request("GET", {{"host", host}}));
  return checked.ok() ? 200 : HttpStatusOf(checked);
}

TEST(OriginPolicyTest, DefaultHostsAreTheListenAddressAndLoopbackAtThePort) {
  const OriginPolicy policy({}, "10.1.2.3", 8080);
  for (const char* host :
       {"10.1.2.3:8080", "localhost:8080", "LOCALHOST:8080", "127.0.0.1:8080", "[::1]:8080"}) {
    EXPECT_EQ(HostStatus(policy, host), 200) << host;
  }
  for (const char* host :
       {"localhost", "localhost:8081", "evil.example:8080", "127.0.0.2:8080", "10.1.2.3", ""}) {
    EXPECT_EQ(HostStatus(policy, host), 421) << host;
  }
  const absl::Status twice =
      policy.CheckHost(Request("GET", {{"host", "localhost:8080"}, {"host", "evil.example"}}));
  EXPECT_EQ(HttpStatusOf(twice), 400);
  const OriginPolicy v6({}, "::", 80);
  EXPECT_EQ(HostStatus(v6, "[::]:80"), 200);
  EXPECT_EQ(HostStatus(v6, "localhost"), 200);  // port 80 is implied
}

TEST(OriginPolicyTest, ConfiguredHosts) {
  const OriginPolicy policy({"ispq.example.com", "proxy.example:8443"}, "0.0.0.0", 8080);
  EXPECT_EQ(HostStatus(policy, "ispq.example.com"), 200);
  EXPECT_EQ(HostStatus(policy, "ISPQ.example.com:9999"), 200);  // a name alone: any port
  EXPECT_EQ(HostStatus(policy, "proxy.example:8443"), 200);
  EXPECT_EQ(HostStatus(policy, "proxy.example:8444"), 421);
  EXPECT_EQ(HostStatus(policy, "localhost:8080"), 421);  // the defaults are replaced
  EXPECT_EQ(HostStatus(OriginPolicy({"*"}, "0.0.0.0", 8080), "anything:1"), 200);
}

TEST(OriginPolicyTest, CredentiallessPostsMustComeFromThisOrigin) {
  const OriginPolicy policy({}, "127.0.0.1", 8080);
  const HttpFields host = {{"host", "127.0.0.1:8080"}};
  EXPECT_TRUE(policy.CheckOrigin(Request("POST", host)).ok());  // no Origin: not a browser's
  HttpFields same = host;
  same.emplace_back("origin", "http://127.0.0.1:8080");
  EXPECT_TRUE(policy.CheckOrigin(Request("POST", same)).ok());
  for (const char* origin : {"null", "http://evil.example", "https://127.0.0.1:8080",
                             "http://127.0.0.1:8081", "file://"}) {
    HttpFields cross = host;
    cross.emplace_back("origin", origin);
    EXPECT_EQ(HttpStatusOf(policy.CheckOrigin(Request("POST", cross))), 403) << origin;
    cross.emplace_back("authorization", "Bearer t");  // a request no other site can make
    EXPECT_TRUE(policy.CheckOrigin(Request("POST", cross)).ok()) << origin;
    EXPECT_TRUE(policy.CheckOrigin(Request("GET", cross)).ok()) << origin;
  }
}

TEST(OriginPolicyTest, ValidatesFlagEntries) {
  for (const char* good : {"*", "localhost", "ispq.example.com:8080", "10.0.0.1", "[::1]:80",
                           "[fe80::1]", "my_host-1"}) {
    EXPECT_TRUE(ValidateAllowedHost(good).ok()) << good;
  }
  for (const char* bad : {"", "host:", "host:0", "host:70000", "a b", "http://host", "host/x",
                          "[::1", "host:8080x"}) {
    EXPECT_FALSE(ValidateAllowedHost(bad).ok()) << bad;
  }
}

}  // namespace
}  // namespace ispq::server::http
