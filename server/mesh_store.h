// Meshes uploaded with CreateMesh, for repeated runs without resending them.
//
// Memory is bounded by a count and by the memory budget: beyond the count, or when the budget
// needs room (server/memory_admission.h), the least recently used mesh is evicted (a job that
// already runs on it keeps its own reference, so eviction never disturbs a job; a later request
// naming the evicted mesh gets NOT_FOUND and uploads it again). Each mesh belongs to the
// principal that created it; the store keeps the owner and leaves access checks to the service.
// Thread-safe.
#ifndef ISPQ_SERVER_MESH_STORE_H_
#define ISPQ_SERVER_MESH_STORE_H_

#include <list>
#include <memory>
#include <string>

#include "absl/base/thread_annotations.h"
#include "absl/container/flat_hash_map.h"
#include "absl/synchronization/mutex.h"
#include "absl/time/time.h"
#include "server/mesh_admission.h"

namespace ispq::server {

struct StoredMesh {
  std::string id;
  AdmittedMesh admitted;  // carries the mesh's memory reservation
  std::string owner;      // the principal that created it
  absl::Time create_time;
};

class MeshStore {
 public:
  explicit MeshStore(int capacity);

  // Stores `admitted` under a new id, evicting the least recently used mesh if full.
  std::shared_ptr<const StoredMesh> Add(AdmittedMesh admitted, std::string owner, absl::Time now);
  // The mesh with this id, marked as used; nullptr if unknown or evicted.
  std::shared_ptr<const StoredMesh> Find(const std::string& id);
  // Whether a mesh was removed.
  bool Remove(const std::string& id);
  // Evicts the least recently used mesh that no job holds; false if there is none.
  bool EvictLeastRecentlyUsed();
  int size() const;

 private:
  using Recency = std::list<std::shared_ptr<const StoredMesh>>;  // most recently used first

  const int capacity_;
  mutable absl::Mutex mutex_;
  Recency recency_ ABSL_GUARDED_BY(mutex_);
  absl::flat_hash_map<std::string, Recency::iterator> by_id_ ABSL_GUARDED_BY(mutex_);
};

}  // namespace ispq::server

#endif  // ISPQ_SERVER_MESH_STORE_H_
