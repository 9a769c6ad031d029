// SPDX-License-Identifier: Apache-2.0
// LowerCurrentThreadPriority (server/jobs/thread_priority.h): the calling thread, and only it,
// runs at niceness 10 afterwards, so that gRPC's threads (health probes among them) keep theirs.
// On Linux the process id names only the main thread, so lowering "the process" from a worker
// would leave the worker alone and slow down the main thread instead: this test would see both.
#include "server/jobs/thread_priority.h"

#include <sys/resource.h>
#include <unistd.h>

#include <thread>

#include "gtest/gtest.h"

namespace ispq::server {
namespace {

int NicenessOf(pid_t thread) { return getpriority(PRIO_PROCESS, static_cast<id_t>(thread)); }

TEST(ThreadPriorityTest, LowersTheCallingThreadOnly) {
  const pid_t main_thread = gettid();
  const int main_before = NicenessOf(main_thread);
  int before = 0;
  int after = 0;
  std::thread worker([&] {
    const pid_t self = gettid();
    // A test run under `nice` starts at niceness 10 or more already; where allowed (as root),
    // the thread is raised back to 0 so that lowering it shows.
    if (NicenessOf(self) >= 10) setpriority(PRIO_PROCESS, static_cast<id_t>(self), 0);
    before = NicenessOf(self);
    LowerCurrentThreadPriority();
    after = NicenessOf(self);
  });
  worker.join();
  if (before >= 10) GTEST_SKIP() << "the test runs at niceness " << before << " already";
  EXPECT_EQ(after, 10);
  EXPECT_EQ(NicenessOf(main_thread), main_before);
}

}  // namespace
}  // namespace ispq::server
