// SPDX-License-Identifier: Apache-2.0
#include "server/memory/memory_budget.h"

#include <optional>
#include <utility>

#include "gtest/gtest.h"

namespace ispq::server {
namespace {

TEST(MemoryBudgetTest, ReservesWithinTheLimitAndReleasesOnDestruction) {
  MemoryBudget budget(1000);
  std::optional<MemoryReservation> jobs = budget.TryReserve(MemoryUse::kJobs, 600);
  ASSERT_TRUE(jobs.has_value());
  EXPECT_EQ(jobs->bytes(), 600);
  EXPECT_FALSE(budget.TryReserve(MemoryUse::kRequests, 401).has_value());
  {
    std::optional<MemoryReservation> request = budget.TryReserve(MemoryUse::kRequests, 400);
    ASSERT_TRUE(request.has_value());
    EXPECT_EQ(budget.used(), 1000);
  }
  EXPECT_EQ(budget.used(), 600);
  EXPECT_EQ(budget.used(MemoryUse::kRequests), 0);
  jobs.reset();
  EXPECT_EQ(budget.used(), 0);
  EXPECT_EQ(budget.ToProto().peak_used_bytes(), 1000);
}

TEST(MemoryBudgetTest, ForcedReservationsMayOverdrawAndBlockLaterOnes) {
  MemoryBudget budget(100);
  MemoryReservation received = budget.ForceReserve(MemoryUse::kRequests, 150);
  EXPECT_EQ(budget.used(), 150);
  EXPECT_FALSE(budget.TryReserve(MemoryUse::kJobs, 1).has_value());
  received.Release();
  EXPECT_EQ(received.bytes(), 0);
  EXPECT_TRUE(budget.TryReserve(MemoryUse::kJobs, 100).has_value());
}

TEST(MemoryBudgetTest, MovedReservationsReleaseOnce) {
  MemoryBudget budget(100);
  MemoryReservation first = budget.ForceReserve(MemoryUse::kResults, 30);
  MemoryReservation second = std::move(first);
  EXPECT_EQ(first.bytes(), 0);  // NOLINT(bugprone-use-after-move): moved-from is empty
  EXPECT_EQ(budget.used(), 30);
  MemoryReservation third = budget.ForceReserve(MemoryUse::kResults, 20);
  third = std::move(second);  // releases the 20 it held
  EXPECT_EQ(budget.used(), 30);
  third.Release();
  EXPECT_EQ(budget.used(), 0);
}

TEST(MemoryBudgetTest, PinnedIsWhatEvictionCannotFree) {
  MemoryBudget budget(1000);
  MemoryReservation request = budget.ForceReserve(MemoryUse::kRequests, 10);
  MemoryReservation job = budget.ForceReserve(MemoryUse::kJobs, 20);
  MemoryReservation mesh = budget.ForceReserve(MemoryUse::kStoredMeshes, 40);
  MemoryReservation result = budget.ForceReserve(MemoryUse::kResults, 80);
  MemoryReservation response = budget.ForceReserve(MemoryUse::kResponses, 160);
  EXPECT_EQ(budget.used(), 310);
  EXPECT_EQ(budget.pinned(), 190);
  const v1::MemoryStats stats = budget.ToProto();
  EXPECT_EQ(stats.limit_bytes(), 1000);
  EXPECT_EQ(stats.requests_bytes(), 10);
  EXPECT_EQ(stats.jobs_bytes(), 20);
  EXPECT_EQ(stats.stored_meshes_bytes(), 40);
  EXPECT_EQ(stats.results_bytes(), 80);
  EXPECT_EQ(stats.responses_bytes(), 160);
}

}  // namespace
}  // namespace ispq::server
