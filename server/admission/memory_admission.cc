// SPDX-License-Identifier: Apache-2.0
#include "server/admission/memory_admission.h"

#include <optional>
#include <string>
#include <utility>

#include "absl/status/status.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "server/jobs/retry_hint.h"

namespace ispq::server {
namespace {

std::string Mebibytes(int64_t bytes) {
  return absl::StrFormat("%.1f MiB", static_cast<double>(bytes) / (1 << 20));
}

}  // namespace

MemoryAdmission::MemoryAdmission(MemoryBudget& budget, JobScheduler& scheduler, MeshStore& meshes,
                                 ServerMetrics& metrics)
    : budget_(budget), scheduler_(scheduler), meshes_(meshes), metrics_(metrics) {}

absl::StatusOr<MemoryReservation> MemoryAdmission::Reserve(MemoryUse use, int64_t bytes,
                                                           absl::string_view what) {
  // Evicting is pointless (and loses what others kept) when even evicting everything would not
  // make room: the rest is held by jobs and requests.
  if (bytes <= budget_.limit() - budget_.pinned()) {
    do {
      if (std::optional<MemoryReservation> reserved = budget_.TryReserve(use, bytes)) {
        return *std::move(reserved);
      }
    } while (EvictOne());
  }
  metrics_.RecordRejectedMemory();
  return Refusal(bytes, what);
}

absl::StatusOr<MemoryReservation> MemoryAdmission::Account(MemoryUse use, int64_t bytes,
                                                           absl::string_view what) {
  MemoryReservation accounted = budget_.ForceReserve(use, bytes);
  while (budget_.used() > budget_.limit()) {
    if (budget_.pinned() > budget_.limit() || !EvictOne()) {
      metrics_.RecordRejectedMemory();
      return Refusal(bytes, what);
    }
  }
  return accounted;
}

bool MemoryAdmission::EvictOne() {
  if (scheduler_.EvictOldestFinished()) {
    metrics_.RecordEvictedResult();
    return true;
  }
  if (meshes_.EvictLeastRecentlyUsed()) {
    metrics_.RecordEvictedMesh();
    return true;
  }
  return false;
}

absl::Status MemoryAdmission::Refusal(int64_t bytes, absl::string_view what) const {
  const int64_t limit = budget_.limit();
  if (bytes > limit) {
    return absl::ResourceExhaustedError(absl::StrCat(
        what, " needs about ", Mebibytes(bytes), ", more than this server's whole memory budget (",
        Mebibytes(limit), ", --max_memory_bytes)"));
  }
  return ResourceExhaustedWithRetryHint(
      absl::StrCat("not enough memory for ", what, ": it needs about ", Mebibytes(bytes), " and ",
                   Mebibytes(budget_.used()), " of the server's ", Mebibytes(limit),
                   " memory budget are held by queued and running jobs and requests"),
      scheduler_.RetryHint());
}

}  // namespace ispq::server
