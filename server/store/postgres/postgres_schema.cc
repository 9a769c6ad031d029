// SPDX-License-Identifier: Apache-2.0
#include "server/store/postgres/postgres_schema.h"

#include <string>
#include <vector>

#include "absl/strings/str_cat.h"
#include "spdlog/spdlog.h"

namespace ispq::server {
namespace {

// An arbitrary key for pg_advisory_xact_lock: the migration lock of ispq.
constexpr int64_t kMigrationLock = 0x69737071;  // "ispq"

// Step i brings the schema from version i to version i + 1.
const std::vector<std::string>& MigrationSteps() {
  static const std::vector<std::string>* steps = new std::vector<std::string>{
      R"sql(
CREATE TABLE ispq_jobs (
  id               text PRIMARY KEY,
  ordinal          bigserial NOT NULL UNIQUE,
  owner            text NOT NULL,
  request_id       text NOT NULL DEFAULT '',
  fingerprint      bytea NOT NULL DEFAULT '',
  bound_to_call    boolean NOT NULL,
  state            integer NOT NULL,
  summary          bytea NOT NULL,
  request          bytea,
  create_time_ns   bigint NOT NULL,
  end_time_ns      bigint,
  next_sequence    bigint NOT NULL,
  cancel_requested boolean NOT NULL DEFAULT false,
  lease_owner      text,
  lease_expires    timestamptz,
  attempts         integer NOT NULL DEFAULT 0
);
CREATE INDEX ispq_jobs_claimable ON ispq_jobs (ordinal) WHERE state IN (1, 2);
CREATE INDEX ispq_jobs_ended ON ispq_jobs (end_time_ns) WHERE end_time_ns IS NOT NULL;
CREATE UNIQUE INDEX ispq_jobs_request_ids ON ispq_jobs (owner, request_id) WHERE request_id <> '';
CREATE TABLE ispq_job_events (
  job_id   text NOT NULL REFERENCES ispq_jobs (id) ON DELETE CASCADE,
  kind     smallint NOT NULL,
  sequence bigint NOT NULL,
  event    bytea NOT NULL,
  PRIMARY KEY (job_id, kind)
);
CREATE TABLE ispq_meshes (
  id             text PRIMARY KEY,
  owner          text NOT NULL,
  stats          bytea NOT NULL,
  mesh           bytea NOT NULL,
  create_time_ns bigint NOT NULL,
  last_used      timestamptz NOT NULL DEFAULT now()
);
)sql",
  };
  return *steps;
}

}  // namespace

absl::Status MigratePostgresSchema(PostgresConnections& connections) {
  absl::Status refused;
  absl::Status ran = connections.Run([&refused](pqxx::connection& connection) {
    pqxx::work work(connection);
    work.exec_params("SELECT pg_advisory_xact_lock($1)", kMigrationLock);
    work.exec("CREATE TABLE IF NOT EXISTS ispq_schema (version integer NOT NULL)");
    pqxx::result rows = work.exec("SELECT version FROM ispq_schema");
    int version = 0;
    if (rows.empty()) {
      work.exec("INSERT INTO ispq_schema VALUES (0)");
    } else {
      version = rows[0][0].as<int>();
    }
    if (version > kPostgresSchemaVersion) {
      refused = absl::FailedPreconditionError(absl::StrCat(
          "the job store's database is at schema version ", version, ", newer than this server's ",
          kPostgresSchemaVersion, ": upgrade the server"));
      return;  // rolled back
    }
    for (int step = version; step < kPostgresSchemaVersion; ++step) {
      work.exec(MigrationSteps()[step]);
      spdlog::info("event=job_store_migrated version={}", step + 1);
    }
    work.exec_params("UPDATE ispq_schema SET version = $1", kPostgresSchemaVersion);
    work.commit();
  });
  if (!refused.ok()) return refused;
  return ran;
}

}  // namespace ispq::server
