// SPDX-License-Identifier: Apache-2.0
#include "server/http/request_body.h"

#include <string>

#include "gtest/gtest.h"
#include "server/http/http_status.h"
#include "server/jobs/job_scheduler.h"
#include "server/store/mesh_store.h"

namespace ispq::server::http {
namespace {

class RequestBodyTest : public ::testing::Test {
 protected:
  static constexpr int64_t kBudget = 1 << 20;

  RequestBodyTest()
      : budget_(kBudget),
        meshes_(100),
        scheduler_({.workers = 1, .max_queued_jobs = 10, .retention = {}}, metrics_, &budget_),
        memory_(budget_, scheduler_, meshes_, metrics_) {}

  ServerMetrics metrics_;
  MemoryBudget budget_;
  InMemoryMeshStore meshes_;
  JobScheduler scheduler_;
  MemoryAdmission memory_;
};

TEST_F(RequestBodyTest, ReservesADeclaredLengthBeforeItArrives) {
  RequestBody body(memory_, 4096);
  ASSERT_TRUE(body.ExpectLength(3000).ok());
  EXPECT_EQ(budget_.used(MemoryUse::kRequests), 3000);
  ASSERT_TRUE(body.Append(std::string(1000, 'a')).ok());
  ASSERT_TRUE(body.Append(std::string(2000, 'b')).ok());
  EXPECT_EQ(budget_.used(MemoryUse::kRequests), 3000);  // nothing more
  EXPECT_EQ(body.TakeBytes().size(), 3000u);
  body.TakeMemory().clear();
  EXPECT_EQ(budget_.used(), 0);
}

TEST_F(RequestBodyTest, GrowsAChunkedBodysReservationAsItArrives) {
  RequestBody body(memory_, kBudget / 2);
  ASSERT_TRUE(body.Append(std::string(10, 'a')).ok());
  const int64_t first = budget_.used(MemoryUse::kRequests);
  EXPECT_GE(first, 10);
  EXPECT_LE(first, 64 << 10);
  for (int i = 0; i < 20; ++i) ASSERT_TRUE(body.Append(std::string(10000, 'b')).ok());
  EXPECT_GE(budget_.used(MemoryUse::kRequests), body.size());
  EXPECT_LE(budget_.used(MemoryUse::kRequests), 2 * body.size() + (64 << 10));
}

TEST_F(RequestBodyTest, RefusesTheByteThatPassesTheLimit) {
  RequestBody body(memory_, 1000);
  ASSERT_TRUE(body.Append(std::string(1000, 'a')).ok());
  const absl::Status refused = body.Append("b");
  EXPECT_EQ(refused.code(), absl::StatusCode::kResourceExhausted);
  EXPECT_EQ(HttpStatusOf(refused), 413);
  EXPECT_EQ(budget_.used(), 0);  // let go at once
}

TEST_F(RequestBodyTest, RefusesWhatTheBudgetCannotHold) {
  MemoryReservation held = budget_.ForceReserve(MemoryUse::kJobs, kBudget - 1000);
  RequestBody declared(memory_, kBudget);
  const absl::Status refused = declared.ExpectLength(5000);
  EXPECT_EQ(refused.code(), absl::StatusCode::kResourceExhausted);
  EXPECT_EQ(HttpStatusOf(refused), 429);
  RequestBody chunked(memory_, kBudget);
  const absl::Status grown = chunked.Append(std::string(500, 'a'));  // its first step is 64 KiB
  EXPECT_EQ(grown.code(), absl::StatusCode::kResourceExhausted);
  EXPECT_EQ(chunked.size(), 0);
  EXPECT_EQ(budget_.used(MemoryUse::kRequests), 0);
}

}  // namespace
}  // namespace ispq::server::http
