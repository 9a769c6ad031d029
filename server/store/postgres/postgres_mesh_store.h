// SPDX-License-Identifier: Apache-2.0
// Stored meshes (CreateMesh) in the PostgreSQL job store's database (table ispq_meshes, see
// server/store/postgres/postgres_schema.h), so that a mesh uploaded through one replica can be
// named in requests to any other. The serialized ispq.v1.TMesh is stored; a replica that needs the
// mesh decodes and validates it again (server/model/mesh_admission.h) and shares the decoded mesh
// between the jobs that hold it at once (a weak cache, so nothing stays in memory that no job
// uses).
//
// The count limit (--max_stored_meshes) holds for the whole database: beyond it, the least
// recently used meshes are deleted. Memory-budget eviction has nothing to evict here: meshes are
// not kept in this process. Thread-safe.
#ifndef ISPQ_SERVER_STORE_POSTGRES_POSTGRES_MESH_STORE_H_
#define ISPQ_SERVER_STORE_POSTGRES_POSTGRES_MESH_STORE_H_

#include <memory>
#include <string>

#include "absl/base/thread_annotations.h"
#include "absl/container/flat_hash_map.h"
#include "absl/synchronization/mutex.h"
#include "server/store/mesh_store.h"
#include "server/store/postgres/postgres_connections.h"

namespace ispq::server {

class PostgresMeshStore final : public MeshStore {
 public:
  // `connections` to a database migrated by PostgresJobStore::Open; `max_arcs` for re-admission.
  PostgresMeshStore(std::shared_ptr<PostgresConnections> connections, int capacity, int max_arcs);

  absl::StatusOr<std::shared_ptr<const StoredMesh>> Add(AdmittedMesh admitted,
                                                        const MeshBytesSource& bytes,
                                                        std::string owner, absl::Time now) override;
  std::shared_ptr<const StoredMesh> Find(const std::string& id) override;
  bool Remove(const std::string& id) override;
  bool EvictLeastRecentlyUsed() override { return false; }
  int size() const override;

 private:
  const std::shared_ptr<PostgresConnections> connections_;
  const int capacity_;
  const int max_arcs_;
  absl::Mutex mutex_;
  absl::flat_hash_map<std::string, std::weak_ptr<const StoredMesh>> decoded_
      ABSL_GUARDED_BY(mutex_);
};

}  // namespace ispq::server

#endif  // ISPQ_SERVER_STORE_POSTGRES_POSTGRES_MESH_STORE_H_
