// SPDX-License-Identifier: Apache-2.0
// PostgresReachability (server/store/postgres/postgres_reachability.h) on a real PostgreSQL: its
// answer while the database answers, when it is stopped or frozen, and again when it is back,
// with the recovery callback run once per recovery.
#include "server/store/postgres/postgres_reachability.h"

#include <atomic>
#include <memory>
#include <string>

#include "absl/strings/ascii.h"
#include "gtest/gtest.h"
#include "server/store/postgres/postgres_connections.h"
#include "tests/support/bounded_wait.h"
#include "tests/support/postgres_suite.h"

namespace ispq::server {
namespace {

using ::ispq::testing::WaitUntil;

constexpr absl::Duration kPeriod = absl::Milliseconds(50);

class PostgresReachabilityTest : public ispq::testing::PostgresSuite {
 protected:
  void SetUp() override {
    ASSERT_TRUE(postgres_->running());
    absl::StatusOr<std::shared_ptr<PostgresConnections>> connections =
        PostgresConnections::Connect({.uri = postgres_->uri(), .size = 1});
    ASSERT_TRUE(connections.ok()) << connections.status();
    connections_ = *connections;
  }

  // When the probe's last `SELECT 1` was answered, as the server saw it; empty if none yet.
  static std::string LastAnsweredProbe() {
    absl::StatusOr<std::string> seen = postgres_->Sql(
        "SELECT max(state_change) FROM pg_stat_activity WHERE query = 'SELECT 1' AND "
        "state = 'idle' AND pid <> pg_backend_pid()");
    return seen.ok() ? std::string(absl::StripAsciiWhitespace(*seen)) : "";
  }
  // Waits until the probe has been answered once more from now on.
  static void AwaitAnsweredProbe() {
    const std::string before = LastAnsweredProbe();
    ASSERT_TRUE(WaitUntil([&] {
      const std::string last = LastAnsweredProbe();
      return !last.empty() && last != before;
    }));
  }

  std::shared_ptr<PostgresConnections> connections_;
  std::atomic<int> recovered_ = 0;
};

TEST_F(PostgresReachabilityTest, UnreachableWhileTheDatabaseIsStoppedAndReachableOnceBack) {
  PostgresReachability reachability(*connections_, kPeriod, absl::Seconds(2),
                                    [this] { ++recovered_; });
  EXPECT_TRUE(reachability.reachable());
  AwaitAnsweredProbe();
  EXPECT_TRUE(reachability.reachable());
  EXPECT_EQ(recovered_, 0) << "nothing to recover from yet";
  ASSERT_TRUE(postgres_->Stop().ok());
  ASSERT_TRUE(WaitUntil([&] { return !reachability.reachable(); }));
  EXPECT_EQ(recovered_, 0);
  ASSERT_TRUE(postgres_->Restart().ok());
  ASSERT_TRUE(WaitUntil([&] { return recovered_ >= 1; }));
  EXPECT_TRUE(reachability.reachable());
  // Later probes that answer are no recovery.
  AwaitAnsweredProbe();
  EXPECT_EQ(recovered_, 1);
}

// A database that hangs without closing anything: each probe ends at its timeout, and the
// probe's connection, cut there, is replaced once the database answers again.
TEST_F(PostgresReachabilityTest, AFrozenDatabaseIsUnreachableUntilItThaws) {
  PostgresReachability reachability(*connections_, kPeriod, absl::Seconds(1),
                                    [this] { ++recovered_; });
  ASSERT_TRUE(postgres_->Freeze().ok());
  ASSERT_TRUE(WaitUntil([&] { return !reachability.reachable(); }));
  ASSERT_TRUE(postgres_->Thaw().ok());
  ASSERT_TRUE(WaitUntil([&] { return recovered_ >= 1; }));
  EXPECT_TRUE(reachability.reachable());
  EXPECT_EQ(recovered_, 1);
}

}  // namespace
}  // namespace ispq::server
