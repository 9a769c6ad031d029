// SPDX-License-Identifier: Apache-2.0
#include "server/http/geometry_cache.h"

#include <utility>

#include "absl/status/status.h"
#include "absl/strings/str_cat.h"
#include "server/http/mesh_geometry.h"
#include "server/model/mesh_positions.h"

namespace ispq::server::http {

GeometryCache::GeometryCache(MemoryAdmission& memory, GeometryCacheOptions options)
    : memory_(memory), options_(options) {}

absl::StatusOr<std::shared_ptr<const std::string>> GeometryCache::Build(
    const std::shared_ptr<const TMesh>& mesh, int max_arcs) {
  const NodePositions* positions = NodePositionsOf(mesh);
  if (positions == nullptr || static_cast<int>(positions->size()) != mesh->num_nodes()) {
    return absl::FailedPreconditionError("the job's mesh has no node positions to draw");
  }
  return std::make_shared<const std::string>(EncodeMeshGeometry(*mesh, *positions, max_arcs));
}

void GeometryCache::Remember(const std::string& job, const std::shared_ptr<const TMesh>& mesh) {
  if (mesh == nullptr) return;
  if (mesh->num_arcs() <= options_.eager_max_arcs) {
    absl::StatusOr<std::shared_ptr<const std::string>> geometry = Build(mesh, options_.max_arcs);
    if (geometry.ok()) Keep(job, *std::move(geometry));
    return;
  }
  absl::MutexLock lock(&mutex_);
  Entry& entry = entries_[job];
  entry.mesh = mesh;
  entry.used = ++clock_;
  EvictLocked();
}

absl::StatusOr<std::shared_ptr<const std::string>> GeometryCache::Get(
    const std::string& job, const std::shared_ptr<const TMesh>& live_mesh) {
  std::shared_ptr<const TMesh> mesh = live_mesh;
  {
    absl::MutexLock lock(&mutex_);
    auto found = entries_.find(job);
    if (found != entries_.end()) {
      found->second.used = ++clock_;
      if (found->second.geometry != nullptr) return found->second.geometry;
      if (mesh == nullptr) mesh = found->second.mesh.lock();
    }
  }
  if (mesh == nullptr) {
    return absl::FailedPreconditionError(absl::StrCat(
        job, " has ended and the server no longer holds its mesh: the geometry is kept for the ",
        options_.capacity, " jobs last drawn or submitted over HTTP"));
  }
  // Built outside the lock: two pages asking at once may both build it, which is harmless.
  absl::StatusOr<std::shared_ptr<const std::string>> geometry = Build(mesh, options_.max_arcs);
  if (geometry.ok()) Keep(job, *geometry);
  return geometry;
}

void GeometryCache::Keep(const std::string& job, std::shared_ptr<const std::string> geometry) {
  absl::StatusOr<MemoryReservation> reserved = memory_.Reserve(
      MemoryUse::kResults, static_cast<int64_t>(geometry->size()), "the web view's geometry");
  if (!reserved.ok()) return;  // answered, not kept
  absl::MutexLock lock(&mutex_);
  Entry& entry = entries_[job];
  entry.mesh.reset();
  entry.geometry = std::move(geometry);
  entry.memory = *std::move(reserved);
  entry.used = ++clock_;
  EvictLocked();
}

void GeometryCache::EvictLocked() {
  while (static_cast<int>(entries_.size()) > options_.capacity) {
    auto oldest = entries_.begin();
    for (auto it = entries_.begin(); it != entries_.end(); ++it) {
      if (it->second.used < oldest->second.used) oldest = it;
    }
    entries_.erase(oldest);
  }
}

int GeometryCache::size() const {
  absl::MutexLock lock(&mutex_);
  return static_cast<int>(entries_.size());
}

}  // namespace ispq::server::http
