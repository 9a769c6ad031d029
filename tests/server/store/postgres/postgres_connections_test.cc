// SPDX-License-Identifier: Apache-2.0
// PostgresConnections (server/store/postgres/postgres_connections.h): the connection parameters it
// adds to a URI (a bound on connecting and keepalives, never overriding what the operator wrote)
// and the bounds it sets on the server's side of its sessions.
#include "server/store/postgres/postgres_connections.h"

#include "gtest/gtest.h"
#include "tests/support/postgres_instance.h"

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

namespace ispq::server {
namespace {

// The server's side of the bounds: a session of ours that stops mid-transaction (its replica
// frozen) is ended by the server after the operation timeout, so its row locks go with it.
TEST(PostgresConnectionsTest, SessionsAreBoundedOnTheServerToo) {
  absl::StatusOr<std::unique_ptr<testing::PostgresInstance>> postgres =
      testing::PostgresInstance::Start();
  ASSERT_TRUE(postgres.ok()) << postgres.status();
  absl::StatusOr<std::shared_ptr<PostgresConnections>> connections = PostgresConnections::Connect(
      {.uri = (*postgres)->uri(), .size = 2, .operation_timeout = absl::Milliseconds(1500)});
  ASSERT_TRUE(connections.ok()) << connections.status();
  std::string idle, statement;
  ASSERT_TRUE((*connections)
                  ->Run([&](pqxx::connection& connection) {
                    pqxx::nontransaction work(connection);
                    idle = work.exec("SHOW idle_in_transaction_session_timeout")[0][0].c_str();
                    statement = work.exec("SHOW statement_timeout")[0][0].c_str();
                  })
                  .ok());
  EXPECT_EQ(idle, "1500ms");
  EXPECT_EQ(statement, "1500ms");
}

}  // namespace
}  // namespace ispq::server
