// SPDX-License-Identifier: Apache-2.0
// WorkerPool (server/jobs/worker_pool.h) over a JobSource the test controls: the pool starts its
// number of threads, each at background priority; every job taken is run to its end and
// reported done once, with the worker's reference dropped first; the threads exit when the
// source is closed and empty, and the destructor joins them.
#include "server/jobs/worker_pool.h"

#include <sys/resource.h>
#include <unistd.h>

#include <deque>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "absl/base/thread_annotations.h"
#include "absl/synchronization/mutex.h"
#include "core/proto/quantization_proto.h"
#include "core/quantization_validator.h"
#include "gtest/gtest.h"
#include "tests/server/server_test_jobs.h"
#include "tests/support/bounded_wait.h"

namespace ispq::server {
namespace {

// This thread's niceness.
int OwnNiceness() { return getpriority(PRIO_PROCESS, static_cast<id_t>(gettid())); }

// Hands out the jobs it is given, blocking workers until there is one or it is closed, and
// records what the workers do.
class TestSource : public JobSource {
 public:
  void Add(std::shared_ptr<Job> job) {
    absl::MutexLock lock(&mutex_);
    pending_.push_back(std::move(job));
  }
  void Close() {
    absl::MutexLock lock(&mutex_);
    closed_ = true;
  }

  std::shared_ptr<Job> Next() override {
    absl::MutexLock lock(&mutex_);
    niceness_.push_back(OwnNiceness());
    ++waiting_;
    mutex_.Await(absl::Condition(
        +[](TestSource* source) ABSL_EXCLUSIVE_LOCKS_REQUIRED(source->mutex_) {
          return !source->pending_.empty() || source->closed_;
        },
        this));
    --waiting_;
    if (pending_.empty()) {
      ++exits_;
      return nullptr;
    }
    std::shared_ptr<Job> job = std::move(pending_.front());
    pending_.pop_front();
    taken_[gettid()] = job;
    return job;
  }

  void Done() override {
    absl::MutexLock lock(&mutex_);
    ++done_;
    // The test keeps one reference to every job; the worker must hold none any more.
    if (taken_[gettid()].use_count() != 1) ++done_while_held_;
    taken_.erase(gettid());
  }

  int waiting() const {
    absl::MutexLock lock(&mutex_);
    return waiting_;
  }
  int done() const {
    absl::MutexLock lock(&mutex_);
    return done_;
  }
  int done_while_held() const {
    absl::MutexLock lock(&mutex_);
    return done_while_held_;
  }
  int exits() const {
    absl::MutexLock lock(&mutex_);
    return exits_;
  }
  std::vector<int> niceness() const {
    absl::MutexLock lock(&mutex_);
    return niceness_;
  }

 private:
  mutable absl::Mutex mutex_;
  std::deque<std::shared_ptr<Job>> pending_ ABSL_GUARDED_BY(mutex_);
  bool closed_ ABSL_GUARDED_BY(mutex_) = false;
  int waiting_ ABSL_GUARDED_BY(mutex_) = 0;
  int done_ ABSL_GUARDED_BY(mutex_) = 0;
  int done_while_held_ ABSL_GUARDED_BY(mutex_) = 0;
  int exits_ ABSL_GUARDED_BY(mutex_) = 0;
  std::map<pid_t, std::weak_ptr<Job>> taken_ ABSL_GUARDED_BY(mutex_);
  std::vector<int> niceness_ ABSL_GUARDED_BY(mutex_);
};

TEST(WorkerPoolTest, StartsItsWorkersAtBackgroundPriorityAndTheyExitWhenTheSourceCloses) {
  const int own_niceness = OwnNiceness();
  ServerMetrics metrics;
  TestSource source;
  {
    WorkerPool pool(3, source, metrics);
    EXPECT_EQ(pool.size(), 3);
    ASSERT_TRUE(testing::WaitUntil([&] { return source.waiting() == 3; }));
    source.Close();
  }  // joins
  EXPECT_EQ(source.exits(), 3);
  EXPECT_EQ(source.done(), 0);
  for (const int niceness : source.niceness()) EXPECT_GE(niceness, 10);
  EXPECT_EQ(OwnNiceness(), own_niceness) << "only the workers' priority is lowered";
}

TEST(WorkerPoolTest, RunsEveryJobToItsEndAndReportsEachDoneOnce) {
  ServerMetrics metrics;
  TestSource source;
  std::vector<std::shared_ptr<Job>> jobs;
  for (int i = 0; i < 4; ++i) {
    jobs.push_back(NewNotchJob("job" + std::to_string(i)));
    source.Add(jobs.back());
  }
  const std::shared_ptr<const TMesh> mesh = jobs.front()->spec().mesh;
  {
    WorkerPool pool(2, source, metrics);
    // Closed with jobs left: the workers still take them all before they exit.
    source.Close();
  }
  EXPECT_EQ(source.done(), 4);
  EXPECT_EQ(source.done_while_held(), 0) << "a worker still held its job when it reported done";
  EXPECT_EQ(source.exits(), 2);
  for (const std::shared_ptr<Job>& job : jobs) {
    ASSERT_TRUE(job->done());
    const v1::Job proto = job->ToProto(v1::FULL);
    ASSERT_EQ(proto.state(), v1::SUCCEEDED);
    const absl::StatusOr<std::vector<int64_t>> q = QuantizationFromProto(proto.result(), *mesh);
    ASSERT_TRUE(q.ok()) << q.status();
    const absl::StatusOr<ValidationReport> report = ValidateQuantization(*mesh, *q);
    ASSERT_TRUE(report.ok()) << report.status();
    EXPECT_TRUE(report->valid()) << report->Describe();
  }
  v1::ServerStats stats;
  metrics.FillProto(stats);
  EXPECT_EQ(stats.finished_total().succeeded(), 4);
}

}  // namespace
}  // namespace ispq::server
