// SPDX-License-Identifier: Apache-2.0
// The workers' job source with a shared store (server/jobs/job_claimer.h), against a store of
// claims kept in memory: local call-bound jobs first, then claims, re-admitted and adopted; a claim
// this replica cannot hold now is given back, one that can never run fails with the reason.
#include "server/jobs/job_claimer.h"

#include <deque>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "absl/synchronization/mutex.h"
#include "gtest/gtest.h"
#include "server/jobs/job_queue.h"
#include "tests/server/server_test_jobs.h"
#include "tests/support/bounded_wait.h"

namespace ispq::server {
namespace {

// Claims handed out once each, in order; what the claimer did with them is recorded.
class ClaimsInMemory : public JobClaims {
 public:
  void Offer(Claim claim) {
    absl::MutexLock lock(&mutex_);
    offered_.push_back(std::move(claim));
  }
  std::optional<Claim> ClaimNext() override {
    absl::MutexLock lock(&mutex_);
    if (offered_.empty()) return std::nullopt;
    Claim claim = std::move(offered_.front());
    offered_.pop_front();
    return claim;
  }
  void Adopt(std::shared_ptr<Job> runner, const Claim& claim) override {
    absl::MutexLock lock(&mutex_);
    adopted_.push_back({runner, claim.id});
  }
  void Release(const Claim& claim) override {
    absl::MutexLock lock(&mutex_);
    released_.push_back(claim.id);
  }
  void Fail(const Claim& claim, const absl::Status& status) override {
    absl::MutexLock lock(&mutex_);
    failed_.push_back({claim.id, status});
  }
  int QueuedCount() override { return -1; }
  void OnClaimable(std::function<void()>) override {}
  void BeginDraining() override {}
  absl::Duration poll_interval() const override { return absl::Milliseconds(1); }

  std::vector<std::string> released() {
    absl::MutexLock lock(&mutex_);
    return released_;
  }
  std::vector<std::pair<std::string, absl::Status>> failed() {
    absl::MutexLock lock(&mutex_);
    return failed_;
  }
  std::vector<std::pair<std::shared_ptr<Job>, std::string>> adopted() {
    absl::MutexLock lock(&mutex_);
    return adopted_;
  }

 private:
  absl::Mutex mutex_;
  std::deque<Claim> offered_ ABSL_GUARDED_BY(mutex_);
  std::vector<std::pair<std::shared_ptr<Job>, std::string>> adopted_ ABSL_GUARDED_BY(mutex_);
  std::vector<std::string> released_ ABSL_GUARDED_BY(mutex_);
  std::vector<std::pair<std::string, absl::Status>> failed_ ABSL_GUARDED_BY(mutex_);
};

JobClaims::Claim ClaimOf(const std::string& id, bool cancel_requested = false) {
  JobClaims::Claim claim;
  claim.id = id;
  claim.create_time = absl::Now();
  claim.next_sequence = 3;
  claim.cancel_requested = cancel_requested;
  claim.attempt = 2;
  return claim;
}

class JobClaimerTest : public ::testing::Test {
 protected:
  JobClaimerTest() : queue_(4), claimer_(queue_, claims_, /*budget=*/nullptr) {}

  // Runs Next() on a thread until `done`, then shuts the queue so that Next() returns.
  std::shared_ptr<Job> NextUntil(const std::function<bool()>& done) {
    std::shared_ptr<Job> next;
    std::thread worker([&] { next = claimer_.Next(); });
    EXPECT_TRUE(testing::WaitUntil(done));
    queue_.CloseAndDrain();
    claimer_.Wake();
    worker.join();
    return next;
  }

  JobQueue queue_;
  ClaimsInMemory claims_;
  JobClaimer claimer_;
};

TEST_F(JobClaimerTest, ServesTheLocalQueueFirstAndClaimsOnlyOnceEnabled) {
  claims_.Offer(ClaimOf("stored"));
  const std::shared_ptr<Job> local = NewNotchJob("local");
  ASSERT_TRUE(queue_.Push(local).ok());
  EXPECT_EQ(claimer_.Next(), local);
  claimer_.Done();
  EXPECT_TRUE(claims_.adopted().empty()) << "claiming is not enabled yet";

  claimer_.EnableClaiming([](const JobClaims::Claim&) { return NotchJobSpec(); });
  const std::shared_ptr<Job> claimed = claimer_.Next();
  ASSERT_NE(claimed, nullptr);
  EXPECT_EQ(claimed->id(), "stored");
  ASSERT_EQ(claims_.adopted().size(), 1u);
  EXPECT_EQ(claims_.adopted()[0].first, claimed);
  EXPECT_EQ(claimed->state(), v1::QUEUED);
  claimer_.Done();
}

TEST_F(JobClaimerTest, AClaimCancelledInTheStoreRunsAsCancelled) {
  claims_.Offer(ClaimOf("cancelled", /*cancel_requested=*/true));
  claimer_.EnableClaiming([](const JobClaims::Claim&) { return NotchJobSpec(); });
  const std::shared_ptr<Job> claimed = claimer_.Next();
  ASSERT_NE(claimed, nullptr);
  EXPECT_FALSE(claimed->Start(absl::Now())) << "a job whose cancel was requested never starts";
  claimer_.Done();
}

TEST_F(JobClaimerTest, GivesBackWhatItCannotHoldNowAndFailsWhatCanNeverRun) {
  claims_.Offer(ClaimOf("no-room"));
  claims_.Offer(ClaimOf("mesh-deleted"));
  claimer_.EnableClaiming([](const JobClaims::Claim& claim) -> absl::StatusOr<JobSpec> {
    if (claim.id == "no-room") return absl::ResourceExhaustedError("not enough memory");
    return absl::FailedPreconditionError("meshes/m was deleted");
  });
  const std::shared_ptr<Job> next =
      NextUntil([&] { return !claims_.released().empty() && !claims_.failed().empty(); });
  EXPECT_EQ(next, nullptr);
  EXPECT_EQ(claims_.released(), std::vector<std::string>{"no-room"});
  const auto failed = claims_.failed();
  ASSERT_EQ(failed.size(), 1u);
  EXPECT_EQ(failed[0].first, "mesh-deleted");
  EXPECT_EQ(failed[0].second.code(), absl::StatusCode::kFailedPrecondition);
  EXPECT_EQ(failed[0].second.message(),
            "the job's request can no longer run: meshes/m was deleted");
  EXPECT_TRUE(claims_.adopted().empty());
  EXPECT_TRUE(queue_.WaitUntilIdle(absl::Now())) << "no claim is left held";
}

}  // namespace
}  // namespace ispq::server
