// SPDX-License-Identifier: Apache-2.0
// PostgresMeshStore (server/store/postgres/postgres_mesh_store.h) on a real PostgreSQL: a stored
// mesh is found by every replica sharing the database (decoded and validated again there),
// removed everywhere, bounded in count for the whole database with the least recently used going
// first, and an unreachable database is told from an unknown mesh.
#include "server/store/postgres/postgres_mesh_store.h"

#include <memory>
#include <string>

#include "absl/strings/ascii.h"
#include "absl/strings/str_cat.h"
#include "google/protobuf/util/message_differencer.h"
#include "gtest/gtest.h"
#include "server/model/mesh_admission.h"
#include "server/store/postgres/postgres_connections.h"
#include "server/store/postgres/postgres_schema.h"
#include "tests/support/postgres_suite.h"
#include "tests/support/test_data.h"

namespace ispq::server {
namespace {

using ::google::protobuf::util::MessageDifferencer;

const absl::Time kT0 = absl::FromUnixSeconds(1'000'000);
constexpr int kMaxArcs = 1000;

const v1::TMesh& Cube() {
  static const v1::TMesh* cube = new v1::TMesh(
      ispq::testing::LoadProtoOrDie(ispq::testing::RealTMeshPath("hex-me/s01c_cube.tmesh.json")));
  return *cube;
}

class PostgresMeshStoreTest : public ispq::testing::PostgresSuite {
 protected:
  void SetUp() override {
    database_ = absl::StrCat("meshes", next_database_++);
    absl::StatusOr<std::string> uri = postgres_->CreateDatabase(database_);
    ASSERT_TRUE(uri.ok()) << uri.status();
    connections_ = Connect();
    ASSERT_NE(connections_, nullptr);
    ASSERT_TRUE(MigratePostgresSchema(*connections_).ok());
  }

  // Another replica's connections to the same database.
  std::shared_ptr<PostgresConnections> Connect() {
    absl::StatusOr<std::shared_ptr<PostgresConnections>> connections =
        PostgresConnections::Connect({.uri = postgres_->uri(database_), .size = 2});
    EXPECT_TRUE(connections.ok()) << connections.status();
    return connections.ok() ? *connections : nullptr;
  }

  // Stores the cube on `store` as the service does; its id.
  static std::string Add(PostgresMeshStore& store, const std::string& owner = "owner") {
    absl::StatusOr<AdmittedMesh> admitted = AdmitMesh(Cube(), kMaxArcs);
    EXPECT_TRUE(admitted.ok()) << admitted.status();
    absl::StatusOr<std::shared_ptr<const StoredMesh>> stored =
        store.Add(*std::move(admitted), Cube(), owner, kT0);
    EXPECT_TRUE(stored.ok()) << stored.status();
    return stored.ok() ? (*stored)->id : "";
  }

  std::string Sql(const std::string& sql) {
    absl::StatusOr<std::string> output = postgres_->Sql(sql, database_);
    return output.ok() ? std::string(absl::StripAsciiWhitespace(*output))
                       : output.status().ToString();
  }
  bool Stored(const std::string& id) {
    return Sql(absl::StrCat("SELECT count(*) FROM ispq_meshes WHERE id = '", id, "'")) == "1";
  }

  std::string database_;
  std::shared_ptr<PostgresConnections> connections_;
};

TEST_F(PostgresMeshStoreTest, AStoredMeshIsFoundOnEveryReplica) {
  PostgresMeshStore here(connections_, 10, kMaxArcs);
  PostgresMeshStore there(Connect(), 10, kMaxArcs);
  absl::StatusOr<AdmittedMesh> admitted = AdmitMesh(Cube(), kMaxArcs);
  ASSERT_TRUE(admitted.ok());
  const v1::MeshStats stats = admitted->stats;
  absl::StatusOr<std::shared_ptr<const StoredMesh>> added =
      here.Add(*std::move(admitted), Cube(), "alice", kT0);
  ASSERT_TRUE(added.ok()) << added.status();
  const std::string id = (*added)->id;
  EXPECT_FALSE(id.empty());
  EXPECT_EQ(here.Find(id), *added) << "the object still held is shared, not decoded again";

  std::shared_ptr<const StoredMesh> found = there.Find(id);
  ASSERT_NE(found, nullptr);
  EXPECT_NE(found, *added);
  EXPECT_EQ(found->id, id);
  EXPECT_EQ(found->owner, "alice");
  EXPECT_EQ(found->create_time, kT0);
  ASSERT_NE(found->admitted.mesh, nullptr);
  EXPECT_TRUE(MessageDifferencer::Equals(found->admitted.stats, stats));
  EXPECT_EQ(there.Find(id), found) << "held on that replica too";
  EXPECT_EQ(here.size(), 1);
  EXPECT_EQ(there.size(), 1);
}

TEST_F(PostgresMeshStoreTest, UnknownMeshesAreNotFound) {
  PostgresMeshStore store(connections_, 10, kMaxArcs);
  EXPECT_EQ(store.Find("nonexistent"), nullptr);
  EXPECT_FALSE(store.Remove("nonexistent"));
  EXPECT_EQ(store.size(), 0);
  EXPECT_FALSE(store.EvictLeastRecentlyUsed()) << "nothing is kept in memory to evict";
}

TEST_F(PostgresMeshStoreTest, ARemovedMeshIsGoneFromEveryReplica) {
  PostgresMeshStore here(connections_, 10, kMaxArcs);
  PostgresMeshStore there(Connect(), 10, kMaxArcs);
  const std::string id = Add(here);
  std::shared_ptr<const StoredMesh> held = there.Find(id);
  ASSERT_NE(held, nullptr);
  EXPECT_TRUE(here.Remove(id));
  EXPECT_FALSE(here.Remove(id));
  EXPECT_EQ(here.Find(id), nullptr);
  EXPECT_EQ(there.Find(id), nullptr) << "even where a job still holds it";
  EXPECT_EQ(there.size(), 0);
}

// The count limit holds for the database, whichever replica stores: beyond it the least recently
// used mesh (stored or found) is deleted.
TEST_F(PostgresMeshStoreTest, BeyondItsCapacityTheLeastRecentlyUsedMeshIsDeleted) {
  PostgresMeshStore here(connections_, 2, kMaxArcs);
  PostgresMeshStore there(Connect(), 2, kMaxArcs);
  const std::string first = Add(here);
  const std::string second = Add(there);
  ASSERT_NE(here.Find(first), nullptr);  // used: now the second is the least recently used
  const std::string third = Add(there);
  EXPECT_EQ(here.size(), 2);
  EXPECT_TRUE(Stored(first));
  EXPECT_FALSE(Stored(second));
  EXPECT_TRUE(Stored(third));
  EXPECT_EQ(here.Find(second), nullptr);
  const std::string fourth = Add(here);
  EXPECT_FALSE(Stored(first));
  EXPECT_TRUE(Stored(third));
  EXPECT_TRUE(Stored(fourth));
}

// A replica decodes a stored mesh anew and admits it under its own limits.
TEST_F(PostgresMeshStoreTest, AStoredMeshIsAdmittedAgainByTheReplicaThatLoadsIt) {
  PostgresMeshStore here(connections_, 10, kMaxArcs);
  PostgresMeshStore smaller(Connect(), 10, /*max_arcs=*/1);
  const std::string id = Add(here);
  EXPECT_EQ(smaller.Find(id), nullptr);
  ASSERT_EQ(Sql(absl::StrCat("UPDATE ispq_meshes SET mesh = '\\x0a0b' WHERE id = '", id, "'")), "");
  PostgresMeshStore there(Connect(), 10, kMaxArcs);
  EXPECT_EQ(there.Find(id), nullptr) << "a stored mesh that no longer decodes";
}

TEST_F(PostgresMeshStoreTest, AnUnreachableDatabaseFailsAddingAndIsNoAnswerOtherwise) {
  PostgresMeshStore store(connections_, 10, kMaxArcs);
  const std::string id = Add(store);
  ASSERT_TRUE(
      postgres_->Sql(absl::StrCat("DROP DATABASE ", database_, " WITH (FORCE)"), "postgres").ok());
  absl::StatusOr<AdmittedMesh> admitted = AdmitMesh(Cube(), kMaxArcs);
  ASSERT_TRUE(admitted.ok());
  EXPECT_EQ(store.Add(*std::move(admitted), Cube(), "owner", kT0).status().code(),
            absl::StatusCode::kUnavailable);
  EXPECT_EQ(store.Find(id), nullptr);
  EXPECT_FALSE(store.Remove(id));
  EXPECT_EQ(store.size(), -1) << "unknown, not zero";
}

}  // namespace
}  // namespace ispq::server
