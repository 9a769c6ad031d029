// SPDX-License-Identifier: Apache-2.0
// The web view's geometry of recent jobs (server/http/mesh_geometry.h), so that a page that asks
// again, or asks after the job has ended, is answered without the mesh. A job lets go of its mesh
// when it ends (server/model/job.h), and a small job may end before the page that submitted it
// asks for its geometry: a job submitted over HTTP is therefore remembered at once, its geometry
// built right away when the mesh is small (cheap, and the only case where the race is likely),
// else the mesh only watched, never kept alive (a large job runs long enough for the page to ask
// while it runs). The cache holds at most `capacity` geometries, least recently used evicted,
// each accounted in the memory budget as retained results are; one the budget refuses is answered
// but not kept.
#ifndef ISPQ_SERVER_HTTP_GEOMETRY_CACHE_H_
#define ISPQ_SERVER_HTTP_GEOMETRY_CACHE_H_

#include <cstdint>
#include <memory>
#include <string>

#include "absl/base/thread_annotations.h"
#include "absl/container/flat_hash_map.h"
#include "absl/status/statusor.h"
#include "absl/synchronization/mutex.h"
#include "core/tmesh.h"
#include "server/admission/memory_admission.h"
#include "server/http/mesh_geometry.h"

namespace ispq::server::http {

struct GeometryCacheOptions {
  int capacity = 16;                    // geometries kept
  int max_arcs = kDefaultGeometryArcs;  // above, the geometry is decimated
  int eager_max_arcs = 20000;           // a submitted mesh up to this size is drawn at once
};

class GeometryCache {
 public:
  explicit GeometryCache(MemoryAdmission& memory, GeometryCacheOptions options = {});

  // A job just submitted, with its mesh (null if it has ended already).
  void Remember(const std::string& job, const std::shared_ptr<const TMesh>& mesh);

  // The geometry of `job`: the cached one, else built from `live_mesh` (the job's mesh while it
  // runs, may be null) or the mesh remembered for it. FAILED_PRECONDITION when there is none.
  absl::StatusOr<std::shared_ptr<const std::string>> Get(
      const std::string& job, const std::shared_ptr<const TMesh>& live_mesh);

  int size() const;

 private:
  struct Entry {
    std::weak_ptr<const TMesh> mesh;              // until the geometry is built
    std::shared_ptr<const std::string> geometry;  // null until built
    MemoryReservation memory;
    uint64_t used = 0;
  };
  // Builds the geometry of `mesh`, or fails if it was not admitted with its positions.
  static absl::StatusOr<std::shared_ptr<const std::string>> Build(
      const std::shared_ptr<const TMesh>& mesh, int max_arcs);
  void Keep(const std::string& job, std::shared_ptr<const std::string> geometry);
  void EvictLocked() ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);

  MemoryAdmission& memory_;
  const GeometryCacheOptions options_;
  mutable absl::Mutex mutex_;
  absl::flat_hash_map<std::string, Entry> entries_ ABSL_GUARDED_BY(mutex_);
  uint64_t clock_ ABSL_GUARDED_BY(mutex_) = 0;
};

}  // namespace ispq::server::http

#endif  // ISPQ_SERVER_HTTP_GEOMETRY_CACHE_H_
