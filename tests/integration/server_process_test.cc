// SPDX-License-Identifier: Apache-2.0
// The test harness's ispq-server launcher (tests/integration/server_process.h) leaves nothing
// behind: a server dies with the test process that started it, even when that process is killed
// by SIGKILL (no destructor runs), and it does not die with a short-lived thread that started it
// (Linux sends the parent-death signal when the forking *thread* exits).
#include "tests/integration/server_process.h"

#include <signal.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <string>
#include <thread>

#include "absl/strings/str_cat.h"
#include "absl/time/clock.h"
#include "absl/time/time.h"
#include "client/health_check.h"
#include "gtest/gtest.h"
#include "tests/integration/death_test_record.h"
#include "tests/integration/service_test_support.h"
#include "tests/support/bounded_wait.h"
#include "tests/support/child_process.h"

namespace ispq::testing {
namespace {

TEST(ServerProcessTest, TheServerDiesWithATestProcessKilledBySigkill) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");  // a fresh process, not a fork of this one
  const std::string record = DeathTestRecordPath();
  EXPECT_EXIT(
      {
        absl::StatusOr<std::unique_ptr<ServerProcess>> server =
            ServerProcess::Start(ServerBinaryPath(), {});
        if (!server.ok()) _exit(1);
        std::ofstream(record) << (*server)->pid() << " " << (*server)->directory() << "\n";
        raise(SIGKILL);
      },
      ::testing::KilledBySignal(SIGKILL), "");
  pid_t server = -1;
  std::string directory;
  std::ifstream(record) >> server >> directory;
  ASSERT_GT(server, 0) << "the child test wrote no record";
  std::filesystem::remove(record);
  const absl::Time died = absl::Now();  // about: the child test has just been reaped
  EXPECT_TRUE(WaitUntil([&] { return !ProcessIsAlive(server); }))
      << "ispq-server " << server << " outlived the test process that started it";
  std::cout << "ispq-server was gone " << absl::FormatDuration(absl::Now() - died)
            << " after the test process died\n";
  std::error_code ignored;
  std::filesystem::remove_all(directory, ignored);  // the killed test could not
}

TEST(ServerProcessTest, AServerStartedFromAShortLivedThreadOutlivesTheThread) {
  std::unique_ptr<ServerProcess> server;
  pid_t starter_id = 0;
  std::thread starter([&] {
    starter_id = gettid();
    server = StartServerOrFail({});
  });
  starter.join();
  ASSERT_NE(server, nullptr);
  // The kernel sends a parent-death signal before it forgets the thread, so once the thread is
  // gone from /proc a server forked by it would have been signalled.
  ASSERT_TRUE(WaitUntil(
      [&] { return !std::filesystem::exists(absl::StrCat("/proc/self/task/", starter_id)); }));
  client::QuantizerClient client = ClientOf(*server);
  const absl::StatusOr<client::ServingStatus> health =
      client::CheckHealth(client.channel(), "", kSafetyNet);
  ASSERT_TRUE(health.ok()) << health.status();
  EXPECT_EQ(*health, client::ServingStatus::kServing);
  EXPECT_TRUE(server->running());
}

}  // namespace
}  // namespace ispq::testing
