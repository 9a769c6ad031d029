// SPDX-License-Identifier: Apache-2.0
// ReadinessMonitor (server/readiness_monitor.h) on a health service that records what it is told:
// "readiness" is known from the first probe on (set before the constructor returns), follows
// the condition as it changes, is set only when it changes, and nothing else is touched:
// liveness (the server's and the Quantizer's status) stays as the server set it.
#include "server/readiness_monitor.h"

#include <atomic>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "absl/base/thread_annotations.h"
#include "absl/synchronization/mutex.h"
#include "gtest/gtest.h"
#include "tests/support/bounded_wait.h"

namespace ispq::server {
namespace {

using ServiceStatus = std::pair<std::string, bool>;

class RecordingHealth : public grpc::HealthCheckServiceInterface {
 public:
  void SetServingStatus(const std::string& service_name, bool serving) override {
    absl::MutexLock lock(&mutex_);
    statuses_.emplace_back(service_name, serving);
  }
  // Every service at once: the monitor must never call this.
  void SetServingStatus(bool serving) override { SetServingStatus("(all services)", serving); }

  std::vector<ServiceStatus> statuses() const {
    absl::MutexLock lock(&mutex_);
    return statuses_;
  }

 private:
  mutable absl::Mutex mutex_;
  std::vector<ServiceStatus> statuses_ ABSL_GUARDED_BY(mutex_);
};

// The condition the monitor polls, counting the polls.
struct Condition {
  std::atomic<bool> ready{false};
  std::atomic<int> polls{0};

  std::function<bool()> Function() {
    return [this] {
      polls.fetch_add(1);
      return ready.load();
    };
  }
};

TEST(ReadinessMonitorTest, TheStatusIsSetBeforeTheConstructorReturns) {
  for (const bool ready : {false, true}) {
    RecordingHealth health;
    Condition condition;
    condition.ready = ready;
    ReadinessMonitor monitor(&health, condition.Function());
    EXPECT_EQ(health.statuses(), std::vector<ServiceStatus>({{kReadinessService, ready}}));
  }
}

TEST(ReadinessMonitorTest, FollowsTheConditionSettingTheStatusOnlyWhenItChanges) {
  RecordingHealth health;
  Condition condition;
  condition.ready = true;
  ReadinessMonitor monitor(&health, condition.Function());

  condition.ready = false;
  ASSERT_TRUE(testing::WaitUntil([&] { return health.statuses().size() == 2; }));
  // Several polls of the same condition later, nothing more was set.
  const int polls = condition.polls.load();
  ASSERT_TRUE(testing::WaitUntil([&] { return condition.polls.load() >= polls + 3; }));
  EXPECT_EQ(health.statuses().size(), 2u);

  condition.ready = true;
  ASSERT_TRUE(testing::WaitUntil([&] { return health.statuses().size() == 3; }));
  EXPECT_EQ(health.statuses(), std::vector<ServiceStatus>({{kReadinessService, true},
                                                           {kReadinessService, false},
                                                           {kReadinessService, true}}));
}

}  // namespace
}  // namespace ispq::server
