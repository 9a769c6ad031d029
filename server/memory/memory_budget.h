// SPDX-License-Identifier: Apache-2.0
// The server's memory budget (--max_memory_bytes): one account of the bytes the server holds on
// behalf of clients, by kind, so that admission can refuse work that would not fit instead of
// letting the process grow until the kernel kills it with every job on it.
//
// What is accounted is an estimate of the heap each thing occupies (see
// server/memory/memory_estimates.h for the estimates); the process also has a fixed base (code,
// gRPC, thread stacks) that the budget does not include. A MemoryReservation is the claim of one
// holder: it releases its bytes when destroyed, so accounting follows ownership (a mesh shared by a
// stored entry and a running job is released when the last of them lets go). TryReserve refuses
// what does not fit; ForceReserve records memory that exists already or must be kept (a received
// request, a finished job's result), which later admissions then see as used. Thread-safe.
#ifndef ISPQ_SERVER_MEMORY_MEMORY_BUDGET_H_
#define ISPQ_SERVER_MEMORY_MEMORY_BUDGET_H_

#include <array>
#include <cstdint>
#include <optional>

#include "absl/base/thread_annotations.h"
#include "absl/synchronization/mutex.h"
#include "ispq/v1/service.pb.h"

namespace ispq::server {

enum class MemoryUse {
  kRequests,      // requests being received, parsed and validated
  kJobs,          // queued and running jobs: their meshes and the solver's working memory
  kStoredMeshes,  // meshes kept from CreateMesh
  kResults,       // results of finished jobs the server retains
  kResponses,     // responses being built and sent
};
inline constexpr int kNumMemoryUses = 5;

class MemoryBudget;

// A claim on the budget, released on destruction. Move-only; empty when default-constructed.
class MemoryReservation {
 public:
  MemoryReservation() = default;
  MemoryReservation(MemoryReservation&& other) noexcept;
  MemoryReservation& operator=(MemoryReservation&& other) noexcept;
  MemoryReservation(const MemoryReservation&) = delete;
  MemoryReservation& operator=(const MemoryReservation&) = delete;
  ~MemoryReservation();

  int64_t bytes() const { return bytes_; }
  // Releases the claim now.
  void Release();

 private:
  friend class MemoryBudget;
  MemoryReservation(MemoryBudget* budget, MemoryUse use, int64_t bytes)
      : budget_(budget), use_(use), bytes_(bytes) {}

  MemoryBudget* budget_ = nullptr;
  MemoryUse use_ = MemoryUse::kRequests;
  int64_t bytes_ = 0;
};

class MemoryBudget {
 public:
  explicit MemoryBudget(int64_t limit_bytes);
  MemoryBudget(const MemoryBudget&) = delete;
  MemoryBudget& operator=(const MemoryBudget&) = delete;

  // Reserves `bytes` (>= 0) if the total stays within the limit.
  std::optional<MemoryReservation> TryReserve(MemoryUse use, int64_t bytes);
  // Reserves `bytes` even beyond the limit.
  MemoryReservation ForceReserve(MemoryUse use, int64_t bytes);

  int64_t limit() const { return limit_; }
  int64_t used() const;
  int64_t used(MemoryUse use) const;
  // Bytes that eviction cannot free: everything but stored meshes and retained results.
  int64_t pinned() const;

  // Limit, use by kind and the peak of the total, for GetServerStats.
  v1::MemoryStats ToProto() const;

 private:
  friend class MemoryReservation;
  void Release(MemoryUse use, int64_t bytes);
  void AddLocked(MemoryUse use, int64_t bytes) ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);

  const int64_t limit_;
  mutable absl::Mutex mutex_;
  std::array<int64_t, kNumMemoryUses> used_ ABSL_GUARDED_BY(mutex_) = {};
  int64_t total_ ABSL_GUARDED_BY(mutex_) = 0;
  int64_t peak_ ABSL_GUARDED_BY(mutex_) = 0;
};

}  // namespace ispq::server

#endif  // ISPQ_SERVER_MEMORY_MEMORY_BUDGET_H_
