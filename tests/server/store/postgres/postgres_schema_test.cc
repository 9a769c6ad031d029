// SPDX-License-Identifier: Apache-2.0
// MigratePostgresSchema (server/store/postgres/postgres_schema.h) on a real PostgreSQL: a fresh
// database is brought to the current version, migrating again changes nothing, replicas that
// start together migrate once, a newer database is refused and an unreachable one says so.
#include "server/store/postgres/postgres_schema.h"

#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "absl/strings/ascii.h"
#include "absl/strings/str_cat.h"
#include "absl/synchronization/notification.h"
#include "gtest/gtest.h"
#include "server/store/postgres/postgres_connections.h"
#include "tests/support/postgres_suite.h"

namespace ispq::server {
namespace {

class PostgresSchemaTest : public ispq::testing::PostgresSuite {
 protected:
  void SetUp() override {
    database_ = absl::StrCat("schema", next_database_++);
    absl::StatusOr<std::string> uri = postgres_->CreateDatabase(database_);
    ASSERT_TRUE(uri.ok()) << uri.status();
    connections_ = Connect();
    ASSERT_NE(connections_, nullptr);
  }

  std::shared_ptr<PostgresConnections> Connect() {
    absl::StatusOr<std::shared_ptr<PostgresConnections>> connections =
        PostgresConnections::Connect({.uri = postgres_->uri(database_), .size = 2});
    EXPECT_TRUE(connections.ok()) << connections.status();
    return connections.ok() ? *connections : nullptr;
  }

  // One SQL command's output in the test's database, trimmed.
  std::string Sql(const std::string& sql) {
    absl::StatusOr<std::string> output = postgres_->Sql(sql, database_);
    return output.ok() ? std::string(absl::StripAsciiWhitespace(*output))
                       : output.status().ToString();
  }
  std::string Tables() {
    return Sql(
        "SELECT string_agg(tablename, ',' ORDER BY tablename) FROM pg_tables WHERE "
        "schemaname = 'public'");
  }

  std::string database_;
  std::shared_ptr<PostgresConnections> connections_;
};

TEST_F(PostgresSchemaTest, BringsAnEmptyDatabaseToTheCurrentVersion) {
  ASSERT_EQ(Tables(), "");
  ASSERT_TRUE(MigratePostgresSchema(*connections_).ok());
  EXPECT_EQ(Tables(), "ispq_job_events,ispq_jobs,ispq_meshes,ispq_schema");
  EXPECT_EQ(Sql("SELECT string_agg(version::text, ',') FROM ispq_schema"),
            absl::StrCat(kPostgresSchemaVersion));
}

// A restarted replica migrates again: nothing is recreated, no row is lost or added.
TEST_F(PostgresSchemaTest, MigratingAgainChangesNothing) {
  ASSERT_TRUE(MigratePostgresSchema(*connections_).ok());
  ASSERT_EQ(Sql("INSERT INTO ispq_meshes (id, owner, stats, mesh, create_time_ns) "
                "VALUES ('kept', 'o', '', '', 1)"),
            "");
  ASSERT_TRUE(MigratePostgresSchema(*connections_).ok());
  ASSERT_TRUE(MigratePostgresSchema(*connections_).ok());
  EXPECT_EQ(Sql("SELECT string_agg(id, ',') FROM ispq_meshes"), "kept");
  EXPECT_EQ(Sql("SELECT string_agg(version::text, ',') FROM ispq_schema"),
            absl::StrCat(kPostgresSchemaVersion));
}

// Replicas starting together on an empty database: the advisory lock makes one migrate and the
// others find the work done, instead of failing on tables created under them.
TEST_F(PostgresSchemaTest, ReplicasMigratingTogetherAllSucceedAndMigrateOnce) {
  constexpr int kReplicas = 4;
  std::vector<std::shared_ptr<PostgresConnections>> replicas;
  for (int i = 0; i < kReplicas; ++i) {
    replicas.push_back(Connect());
    ASSERT_NE(replicas.back(), nullptr);
  }
  std::vector<absl::Status> migrated(kReplicas);
  absl::Notification go;
  std::vector<std::thread> threads;
  for (int i = 0; i < kReplicas; ++i) {
    threads.emplace_back([&, i] {
      go.WaitForNotification();
      migrated[i] = MigratePostgresSchema(*replicas[i]);
    });
  }
  go.Notify();
  for (std::thread& thread : threads) thread.join();
  for (int i = 0; i < kReplicas; ++i) EXPECT_TRUE(migrated[i].ok()) << i << ": " << migrated[i];
  EXPECT_EQ(Sql("SELECT string_agg(version::text, ',') FROM ispq_schema"),
            absl::StrCat(kPostgresSchemaVersion));
}

// An older replica must not write a database a newer one migrated: refused, and left as it is.
TEST_F(PostgresSchemaTest, RefusesADatabaseAtANewerVersion) {
  ASSERT_TRUE(MigratePostgresSchema(*connections_).ok());
  const std::string newer = absl::StrCat(kPostgresSchemaVersion + 1);
  ASSERT_EQ(Sql(absl::StrCat("UPDATE ispq_schema SET version = ", newer)), "");
  const absl::Status refused = MigratePostgresSchema(*connections_);
  EXPECT_EQ(refused.code(), absl::StatusCode::kFailedPrecondition) << refused;
  EXPECT_NE(refused.message().find(newer), std::string::npos) << refused;
  EXPECT_EQ(Sql("SELECT string_agg(version::text, ',') FROM ispq_schema"), newer);
}

TEST_F(PostgresSchemaTest, AnUnreachableDatabaseIsUnavailable) {
  // The database vanishes under the pool's connection: reconnecting is refused.
  ASSERT_TRUE(
      postgres_->Sql(absl::StrCat("DROP DATABASE ", database_, " WITH (FORCE)"), "postgres").ok());
  EXPECT_EQ(MigratePostgresSchema(*connections_).code(), absl::StatusCode::kUnavailable);
}

}  // namespace
}  // namespace ispq::server
