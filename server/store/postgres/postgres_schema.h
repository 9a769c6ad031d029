// SPDX-License-Identifier: Apache-2.0
// The job store's tables in PostgreSQL, created and migrated by the server at start.
//
// Versioned: table ispq_schema holds the version the database is at; Migrate applies the steps
// above it in order, each in one transaction, under an advisory lock so that replicas starting
// together migrate once. A database at a newer version than this binary knows is refused (an
// older replica must not write what it does not understand).
//
// Version 1:
//   ispq_jobs        one row per retained job: its summary (an ispq.v1.Job without result, as
//                    GetJob answers it), state, the serialized request while it has not ended
//                    (so that any replica can run it), times, request id and fingerprint, the
//                    lease (owner replica, expiry) and whether cancellation was requested;
//                    `ordinal` orders it for listing.
//   ispq_job_events  the kept events of each job, at most one per kind (accepted, latest
//                    progress, latest intermediate, terminal): the bound of
//                    server/model/job_event_log.h.
//   ispq_meshes      stored meshes (CreateMesh): the serialized ispq.v1.TMesh and its stats.
#ifndef ISPQ_SERVER_STORE_POSTGRES_POSTGRES_SCHEMA_H_
#define ISPQ_SERVER_STORE_POSTGRES_POSTGRES_SCHEMA_H_

#include "absl/status/status.h"
#include "server/store/postgres/postgres_connections.h"

namespace ispq::server {

inline constexpr int kPostgresSchemaVersion = 1;

// Kinds of ispq_job_events rows.
enum class StoredEventKind : int { kAccepted = 0, kProgress = 1, kIntermediate = 2, kTerminal = 3 };

// Brings the database to kPostgresSchemaVersion. FAILED_PRECONDITION for a newer database,
// UNAVAILABLE if it cannot be reached.
absl::Status MigratePostgresSchema(PostgresConnections& connections);

}  // namespace ispq::server

#endif  // ISPQ_SERVER_STORE_POSTGRES_POSTGRES_SCHEMA_H_
