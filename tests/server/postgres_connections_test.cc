// The connection parameters PostgresConnections adds to a URI (server/postgres_connections.h):
// a bound on connecting and keepalives, never overriding what the operator wrote.
#include "server/postgres_connections.h"

#include "gtest/gtest.h"

namespace ispq::server {
namespace {

TEST(WithConnectionDefaultsTest, AddsABoundOnConnectingAndKeepalives) {
  EXPECT_EQ(WithConnectionDefaults("postgresql://u@h:5432/db", absl::Seconds(10)),
            "postgresql://u@h:5432/db?connect_timeout=10&keepalives=1&keepalives_idle=10&"
            "keepalives_interval=5&keepalives_count=3");
  EXPECT_EQ(WithConnectionDefaults("postgresql://u@h/db?sslmode=require", absl::Seconds(10)),
            "postgresql://u@h/db?sslmode=require&connect_timeout=10&keepalives=1&"
            "keepalives_idle=10&keepalives_interval=5&keepalives_count=3");
}

TEST(WithConnectionDefaultsTest, RoundsTheBoundUpToWholeSecondsOfAtLeastTwo) {
  EXPECT_NE(WithConnectionDefaults("postgresql://h/db", absl::Milliseconds(2500))
                .find("connect_timeout=3&"),
            std::string::npos);
  EXPECT_NE(WithConnectionDefaults("postgresql://h/db", absl::Milliseconds(300))
                .find("connect_timeout=2&"),
            std::string::npos);
}

TEST(WithConnectionDefaultsTest, KeepsWhatTheUriSetsItself) {
  const std::string uri = WithConnectionDefaults(
      "postgresql://h/db?connect_timeout=30&keepalives_idle=60", absl::Seconds(5));
  EXPECT_NE(uri.find("?connect_timeout=30&keepalives_idle=60&keepalives=1&"), std::string::npos)
      << uri;
  EXPECT_EQ(uri.find("connect_timeout=5"), std::string::npos) << uri;
  EXPECT_EQ(uri.find("keepalives_idle=10"), std::string::npos) << uri;
}

}  // namespace
}  // namespace ispq::server
