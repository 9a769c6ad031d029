// SPDX-License-Identifier: Apache-2.0
#include <algorithm>
#include <iterator>
#include <utility>

#include "server/model/resource_names.h"
#include "server/store/mesh_store.h"

namespace ispq::server {

InMemoryMeshStore::InMemoryMeshStore(int capacity) : capacity_(capacity) {}

absl::StatusOr<std::shared_ptr<const StoredMesh>> InMemoryMeshStore::Add(
    AdmittedMesh admitted, const MeshBytesSource& /*bytes*/, std::string owner, absl::Time now) {
  auto stored = std::make_shared<StoredMesh>();
  stored->admitted = std::move(admitted);
  stored->owner = std::move(owner);
  stored->create_time = now;
  absl::MutexLock lock(&mutex_);
  do {
    stored->id = NewResourceId();
  } while (by_id_.contains(stored->id));
  while (!recency_.empty() && static_cast<int>(recency_.size()) >= capacity_) {
    by_id_.erase(recency_.back()->id);
    recency_.pop_back();
  }
  recency_.push_front(stored);
  by_id_[stored->id] = recency_.begin();
  return std::shared_ptr<const StoredMesh>(stored);
}

std::shared_ptr<const StoredMesh> InMemoryMeshStore::Find(const std::string& id) {
  absl::MutexLock lock(&mutex_);
  const auto it = by_id_.find(id);
  if (it == by_id_.end()) return nullptr;
  recency_.splice(recency_.begin(), recency_, it->second);
  return *it->second;
}

bool InMemoryMeshStore::Remove(const std::string& id) {
  absl::MutexLock lock(&mutex_);
  const auto it = by_id_.find(id);
  if (it == by_id_.end()) return false;
  recency_.erase(it->second);
  by_id_.erase(it);
  return true;
}

bool InMemoryMeshStore::EvictLeastRecentlyUsed() {
  std::shared_ptr<const StoredMesh> evicted;  // released after the lock, like any last reference
  absl::MutexLock lock(&mutex_);
  // A mesh that a job holds would stay in memory anyway: evicting it would only lose it.
  const auto unused = std::find_if(recency_.rbegin(), recency_.rend(), [](const auto& stored) {
    return stored->admitted.mesh.use_count() == 1;
  });
  if (unused == recency_.rend()) return false;
  evicted = *unused;
  by_id_.erase(evicted->id);
  recency_.erase(std::next(unused).base());
  return true;
}

int InMemoryMeshStore::size() const {
  absl::MutexLock lock(&mutex_);
  return static_cast<int>(recency_.size());
}

}  // namespace ispq::server
