// SPDX-License-Identifier: Apache-2.0
#include "server/memory/memory_budget.h"

#include <algorithm>
#include <utility>

namespace ispq::server {

MemoryReservation::MemoryReservation(MemoryReservation&& other) noexcept
    : budget_(std::exchange(other.budget_, nullptr)),
      use_(other.use_),
      bytes_(std::exchange(other.bytes_, 0)) {}

MemoryReservation& MemoryReservation::operator=(MemoryReservation&& other) noexcept {
  if (this != &other) {
    Release();
    budget_ = std::exchange(other.budget_, nullptr);
    use_ = other.use_;
    bytes_ = std::exchange(other.bytes_, 0);
  }
  return *this;
}

MemoryReservation::~MemoryReservation() { Release(); }

void MemoryReservation::Release() {
  if (budget_ != nullptr) budget_->Release(use_, bytes_);
  budget_ = nullptr;
  bytes_ = 0;
}

MemoryBudget::MemoryBudget(int64_t limit_bytes) : limit_(limit_bytes) {}

void MemoryBudget::AddLocked(MemoryUse use, int64_t bytes) {
  used_[static_cast<int>(use)] += bytes;
  total_ += bytes;
  peak_ = std::max(peak_, total_);
}

std::optional<MemoryReservation> MemoryBudget::TryReserve(MemoryUse use, int64_t bytes) {
  bytes = std::max<int64_t>(bytes, 0);
  absl::MutexLock lock(&mutex_);
  if (bytes > limit_ - total_) return std::nullopt;
  AddLocked(use, bytes);
  return MemoryReservation(this, use, bytes);
}

MemoryReservation MemoryBudget::ForceReserve(MemoryUse use, int64_t bytes) {
  bytes = std::max<int64_t>(bytes, 0);
  absl::MutexLock lock(&mutex_);
  AddLocked(use, bytes);
  return MemoryReservation(this, use, bytes);
}

void MemoryBudget::Release(MemoryUse use, int64_t bytes) {
  absl::MutexLock lock(&mutex_);
  used_[static_cast<int>(use)] -= bytes;
  total_ -= bytes;
}

int64_t MemoryBudget::used() const {
  absl::MutexLock lock(&mutex_);
  return total_;
}

int64_t MemoryBudget::used(MemoryUse use) const {
  absl::MutexLock lock(&mutex_);
  return used_[static_cast<int>(use)];
}

int64_t MemoryBudget::pinned() const {
  absl::MutexLock lock(&mutex_);
  return total_ - used_[static_cast<int>(MemoryUse::kStoredMeshes)] -
         used_[static_cast<int>(MemoryUse::kResults)];
}

v1::MemoryStats MemoryBudget::ToProto() const {
  v1::MemoryStats stats;
  stats.set_limit_bytes(limit_);
  absl::MutexLock lock(&mutex_);
  stats.set_used_bytes(total_);
  stats.set_peak_used_bytes(peak_);
  stats.set_requests_bytes(used_[static_cast<int>(MemoryUse::kRequests)]);
  stats.set_jobs_bytes(used_[static_cast<int>(MemoryUse::kJobs)]);
  stats.set_stored_meshes_bytes(used_[static_cast<int>(MemoryUse::kStoredMeshes)]);
  stats.set_results_bytes(used_[static_cast<int>(MemoryUse::kResults)]);
  stats.set_responses_bytes(used_[static_cast<int>(MemoryUse::kResponses)]);
  return stats;
}

}  // namespace ispq::server
