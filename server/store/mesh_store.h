// SPDX-License-Identifier: Apache-2.0
// Meshes uploaded with CreateMesh, for repeated runs without resending them.
//
// Memory is bounded by a count and by the memory budget: beyond the count, or when the budget
// needs room (server/admission/memory_admission.h), the least recently used mesh is evicted (a job
// that already runs on it keeps its own reference, so eviction never disturbs a job; a later
// request naming the evicted mesh gets NOT_FOUND and uploads it again). Each mesh belongs to the
// principal that created it; the store keeps the owner and leaves access checks to the service.
// Thread-safe.
//
// Two implementations: InMemoryMeshStore below (the default) and PostgresMeshStore
// (server/store/postgres/postgres_mesh_store.h), which every replica sharing the database sees.
#ifndef ISPQ_SERVER_STORE_MESH_STORE_H_
#define ISPQ_SERVER_STORE_MESH_STORE_H_

#include <functional>
#include <list>
#include <memory>
#include <string>
#include <utility>

#include "absl/base/thread_annotations.h"
#include "absl/container/flat_hash_map.h"
#include "absl/status/statusor.h"
#include "absl/synchronization/mutex.h"
#include "absl/time/time.h"
#include "ispq/v1/tmesh.pb.h"
#include "server/model/mesh_admission.h"

namespace ispq::server {

// The binary protobuf of a mesh being stored, made only for a store that keeps it (the shared
// store does; the in-memory one keeps the decoded mesh alone): from the message it was decoded
// from, or from the bytes it was decoded from when it was never one message (an upload).
class MeshBytesSource {
 public:
  MeshBytesSource(const v1::TMesh& proto)  // NOLINT(google-explicit-constructor): the usual case
      : serialize_([&proto] { return proto.SerializeAsString(); }) {}
  explicit MeshBytesSource(std::function<std::string()> serialize)
      : serialize_(std::move(serialize)) {}

  std::string Serialize() const { return serialize_(); }

 private:
  std::function<std::string()> serialize_;
};

struct StoredMesh {
  std::string id;
  AdmittedMesh admitted;  // carries the mesh's memory reservation
  std::string owner;      // the principal that created it
  absl::Time create_time;
};

class MeshStore {
 public:
  virtual ~MeshStore() = default;

  // Stores `admitted` (validated from `bytes`) under a new id. UNAVAILABLE if a shared store
  // cannot be reached.
  virtual absl::StatusOr<std::shared_ptr<const StoredMesh>> Add(AdmittedMesh admitted,
                                                                const MeshBytesSource& bytes,
                                                                std::string owner,
                                                                absl::Time now) = 0;
  // The mesh with this id, marked as used; nullptr if unknown or evicted.
  virtual std::shared_ptr<const StoredMesh> Find(const std::string& id) = 0;
  // Whether a mesh was removed.
  virtual bool Remove(const std::string& id) = 0;
  // Evicts the least recently used mesh that no job holds from this process's memory; false if
  // there is none.
  virtual bool EvictLeastRecentlyUsed() = 0;
  virtual int size() const = 0;
};

// The default: meshes in this process's memory, within the memory budget.
class InMemoryMeshStore final : public MeshStore {
 public:
  explicit InMemoryMeshStore(int capacity);

  absl::StatusOr<std::shared_ptr<const StoredMesh>> Add(AdmittedMesh admitted,
                                                        const MeshBytesSource& bytes,
                                                        std::string owner, absl::Time now) override;
  std::shared_ptr<const StoredMesh> Find(const std::string& id) override;
  bool Remove(const std::string& id) override;
  bool EvictLeastRecentlyUsed() override;
  int size() const override;

 private:
  using Recency = std::list<std::shared_ptr<const StoredMesh>>;  // most recently used first

  const int capacity_;
  mutable absl::Mutex mutex_;
  Recency recency_ ABSL_GUARDED_BY(mutex_);
  absl::flat_hash_map<std::string, Recency::iterator> by_id_ ABSL_GUARDED_BY(mutex_);
};

}  // namespace ispq::server

#endif  // ISPQ_SERVER_STORE_MESH_STORE_H_
