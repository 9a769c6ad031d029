// SPDX-License-Identifier: Apache-2.0
// Admission against the memory budget (server/memory/memory_budget.h). A claim that does not fit
// first makes room by evicting what the server keeps only for later retrieval: finished jobs
// (oldest ended first), then stored meshes (least recently used first). Only when nothing evictable
// is left is it refused: RESOURCE_EXHAUSTED with a retry hint (server/jobs/retry_hint.h), or
// without one when the claim is larger than the whole budget and could never fit. Refusals and
// evictions are counted in the server metrics. Thread-safe.
#ifndef ISPQ_SERVER_ADMISSION_MEMORY_ADMISSION_H_
#define ISPQ_SERVER_ADMISSION_MEMORY_ADMISSION_H_

#include <cstdint>

#include "absl/status/statusor.h"
#include "absl/strings/string_view.h"
#include "server/jobs/job_scheduler.h"
#include "server/memory/memory_budget.h"
#include "server/metrics/server_metrics.h"
#include "server/store/mesh_store.h"

namespace ispq::server {

class MemoryAdmission {
 public:
  // Everything referenced must outlive this object.
  MemoryAdmission(MemoryBudget& budget, JobScheduler& scheduler, MeshStore& meshes,
                  ServerMetrics& metrics);

  // Claims `bytes` for memory about to be allocated for `what` (named in a refusal).
  absl::StatusOr<MemoryReservation> Reserve(MemoryUse use, int64_t bytes, absl::string_view what);
  // Records `bytes` that are allocated already (a received request) and refuses, as Reserve,
  // when they leave the budget overdrawn; the caller then lets go of the memory.
  absl::StatusOr<MemoryReservation> Account(MemoryUse use, int64_t bytes, absl::string_view what);

  MemoryBudget& budget() { return budget_; }

 private:
  // Evicts one finished job or stored mesh; false if there is none.
  bool EvictOne();
  absl::Status Refusal(int64_t bytes, absl::string_view what) const;

  MemoryBudget& budget_;
  JobScheduler& scheduler_;
  MeshStore& meshes_;
  ServerMetrics& metrics_;
};

}  // namespace ispq::server

#endif  // ISPQ_SERVER_ADMISSION_MEMORY_ADMISSION_H_
