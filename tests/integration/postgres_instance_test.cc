// SPDX-License-Identifier: Apache-2.0
// The test harness's PostgreSQL (tests/support/postgres_instance.h) does what a fault suite relies
// on: a frozen instance hangs without closing connections and answers again once thawed; a
// stopped one refuses connections and a restarted one has its data on the same port; nothing of
// it is left running after its destructor, nor after the test process is killed (frozen or not).
// Waits are bounded only as a safety net; what must *not* happen (an answer from a frozen
// database) is given a short window, which a loaded machine can only make easier to pass.
#include "tests/support/postgres_instance.h"

#include <libpq-fe.h>
#include <poll.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <string>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "absl/time/clock.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "tests/integration/death_test_record.h"
#include "tests/support/bounded_wait.h"
#include "tests/support/child_process.h"

namespace ispq::testing {
namespace {

using ::testing::Contains;
using ::testing::HasSubstr;
using ::testing::IsEmpty;

using Connection = std::unique_ptr<PGconn, decltype(&PQfinish)>;

// A libpq connection to `uri` that gives up after `connect_timeout_seconds` (libpq's minimum
// is 2).
Connection Connect(const std::string& uri, int connect_timeout_seconds) {
  const std::string with_timeout = absl::StrCat(uri, "?connect_timeout=", connect_timeout_seconds);
  return Connection(PQconnectdb(with_timeout.c_str()), &PQfinish);
}

bool Connected(const Connection& connection) {
  return connection != nullptr && PQstatus(connection.get()) == CONNECTION_OK;
}

// Waits up to `timeout` for the answer to the query sent last (PQsendQuery): the first value of
// its first row, or nullopt if no answer came or the query failed.
std::optional<std::string> AnswerWithin(PGconn* connection, absl::Duration timeout) {
  const absl::Time deadline = absl::Now() + timeout;
  while (true) {
    if (PQconsumeInput(connection) == 0) return std::nullopt;  // the connection broke
    if (PQisBusy(connection) == 0) break;
    const absl::Duration left = deadline - absl::Now();
    if (left <= absl::ZeroDuration()) return std::nullopt;
    pollfd readable{PQsocket(connection), POLLIN, 0};
    poll(&readable, 1, static_cast<int>(std::min<int64_t>(absl::ToInt64Milliseconds(left), 100)));
  }
  std::optional<std::string> value;
  while (PGresult* result = PQgetResult(connection)) {
    if (PQresultStatus(result) == PGRES_TUPLES_OK && PQntuples(result) > 0) {
      value = PQgetvalue(result, 0, 0);
    }
    PQclear(result);
  }
  return value;
}

std::unique_ptr<PostgresInstance> StartOrFail() {
  absl::StatusOr<std::unique_ptr<PostgresInstance>> started = PostgresInstance::Start();
  EXPECT_TRUE(started.ok()) << started.status();
  return started.ok() ? *std::move(started) : nullptr;
}

std::string Pids(const std::vector<pid_t>& pids) { return absl::StrJoin(pids, " "); }

// The name of the instance's directory, which every process of the instance shows.
std::string NameOf(const PostgresInstance& postgres) {
  return std::filesystem::path(postgres.directory()).filename();
}

TEST(PostgresInstanceTest, StartsAnswersAndNamesItsDirectoryInEveryProcess) {
  std::unique_ptr<PostgresInstance> postgres = StartOrFail();
  ASSERT_NE(postgres, nullptr);
  EXPECT_TRUE(postgres->running());
  EXPECT_FALSE(postgres->frozen());
  ASSERT_EQ(postgres->Sql("SELECT 40 + 2").value_or("failed"), "42\n");
  const absl::StatusOr<std::string> uri = postgres->CreateDatabase("own");
  ASSERT_TRUE(uri.ok()) << uri.status();
  const Connection connected = Connect(*uri, 60);
  EXPECT_TRUE(Connected(connected)) << postgres->Log();
  const std::vector<pid_t> children = ChildrenOf(postgres->pid());
  EXPECT_GE(children.size(), 4u) << "checkpointer, background writer, WAL writer, a backend, ...";
  EXPECT_THAT(ProcessesWithCommandLineContaining(NameOf(*postgres)), Contains(postgres->pid()));
  for (pid_t child : children) {
    // Unless it ended meanwhile (e.g. the backend of CreateDatabase's psql). A child sets its
    // title after it was forked (one read it without the name in a CI run): asked until it shows
    // the name or ends, within the safety net.
    EXPECT_TRUE(testing::WaitUntil([&] {
      return std::ranges::count(ProcessesWithCommandLineContaining(NameOf(*postgres)), child) ==
                 1 ||
             !ProcessIsAlive(child);
    })) << child;
  }
}

TEST(PostgresInstanceTest, AFrozenInstanceHangsWithoutClosingConnectionsUntilThawed) {
  std::unique_ptr<PostgresInstance> postgres = StartOrFail();
  ASSERT_NE(postgres, nullptr);
  const Connection held = Connect(postgres->uri(), 60);
  ASSERT_TRUE(Connected(held)) << PQerrorMessage(held.get());

  ASSERT_TRUE(postgres->Freeze().ok());
  EXPECT_TRUE(postgres->frozen());
  EXPECT_TRUE(ProcessIsStopped(postgres->pid()));
  const std::vector<pid_t> backends = ChildrenOf(postgres->pid());
  EXPECT_GE(backends.size(), 4u);
  for (pid_t backend : backends) EXPECT_TRUE(ProcessIsStopped(backend)) << backend;
  ASSERT_EQ(PQsendQuery(held.get(), "SELECT 42"), 1) << PQerrorMessage(held.get());
  EXPECT_EQ(AnswerWithin(held.get(), absl::Seconds(2)), std::nullopt)
      << "a frozen database cannot answer";
  EXPECT_EQ(PQstatus(held.get()), CONNECTION_OK) << "nor close the connection";
  // A new client reaches the kernel's listen queue, then waits for an answer that never comes.
  EXPECT_TRUE(LoopbackPortAcceptsConnections(postgres->port()));
  const Connection fresh = Connect(postgres->uri(), 2);
  EXPECT_FALSE(Connected(fresh));
  EXPECT_THAT(PQerrorMessage(fresh.get()), HasSubstr("timeout"));

  ASSERT_TRUE(postgres->Thaw().ok());
  EXPECT_FALSE(postgres->frozen());
  EXPECT_EQ(AnswerWithin(held.get(), kSafetyNet), "42") << "the held connection goes on";
  EXPECT_TRUE(Connected(Connect(postgres->uri(), 60))) << postgres->Log();
}

class PostgresStopTest : public ::testing::TestWithParam<PostgresInstance::StopMode> {};

TEST_P(PostgresStopTest, AStoppedInstanceRefusesConnectionsAndARestartedOneKeepsItsData) {
  std::unique_ptr<PostgresInstance> postgres = StartOrFail();
  ASSERT_NE(postgres, nullptr);
  const int port = postgres->port();
  const std::string uri = postgres->uri();
  // Committed just before the stop: an immediate stop (a crash, for PostgreSQL) keeps it too.
  ASSERT_TRUE(postgres->Sql("CREATE TABLE kept (v int); INSERT INTO kept VALUES (7)").ok());
  const Connection held = Connect(uri, 60);
  ASSERT_TRUE(Connected(held));

  ASSERT_TRUE(postgres->Stop(GetParam()).ok()) << postgres->Log();
  EXPECT_FALSE(postgres->running());
  EXPECT_EQ(postgres->pid(), -1);
  EXPECT_FALSE(LoopbackPortAcceptsConnections(port));
  const Connection refused = Connect(uri, 60);
  EXPECT_FALSE(Connected(refused));
  EXPECT_THAT(PQerrorMessage(refused.get()), HasSubstr("refused"));
  PGresult* broken = PQexec(held.get(), "SELECT 1");
  EXPECT_NE(PQresultStatus(broken), PGRES_TUPLES_OK) << "the held connection was closed";
  PQclear(broken);

  ASSERT_TRUE(postgres->Restart().ok()) << postgres->Log();
  EXPECT_TRUE(postgres->running());
  EXPECT_EQ(postgres->port(), port);
  EXPECT_EQ(postgres->uri(), uri);
  EXPECT_EQ(postgres->Sql("SELECT v FROM kept").value_or("failed"), "7\n");
  // Restarting a running instance stops it first.
  ASSERT_TRUE(postgres->Restart().ok()) << postgres->Log();
  EXPECT_EQ(postgres->Sql("SELECT v FROM kept").value_or("failed"), "7\n");
}

INSTANTIATE_TEST_SUITE_P(Modes, PostgresStopTest,
                         ::testing::Values(PostgresInstance::StopMode::kFast,
                                           PostgresInstance::StopMode::kImmediate),
                         [](const ::testing::TestParamInfo<PostgresInstance::StopMode>& mode) {
                           return mode.param == PostgresInstance::StopMode::kFast ? "Fast"
                                                                                  : "Immediate";
                         });

TEST(PostgresInstanceTest, TheDestructorLeavesNoProcessAndNoDirectoryBehind) {
  std::unique_ptr<PostgresInstance> postgres = StartOrFail();
  ASSERT_NE(postgres, nullptr);
  const std::string directory = postgres->directory();
  const std::string name = NameOf(*postgres);
  const Connection idle = Connect(postgres->uri(), 60);  // a backend waiting for its client
  ASSERT_TRUE(Connected(idle));
  std::vector<pid_t> processes = ChildrenOf(postgres->pid());
  processes.push_back(postgres->pid());
  ASSERT_TRUE(postgres->Freeze().ok());  // the hardest case: every process stopped

  postgres.reset();
  for (pid_t pid : processes) EXPECT_FALSE(ProcessIsAlive(pid)) << pid;
  EXPECT_THAT(ProcessesWithCommandLineContaining(name), IsEmpty());
  EXPECT_FALSE(std::filesystem::exists(directory));
}

// Starts an instance in a child test process that then dies by SIGKILL, as a test killed by
// ctest's timeout would; every process of the instance must end without the test's help, and
// the directory (a cluster is about 40 MB) must go too.
class PostgresOfAKilledTestTest : public ::testing::TestWithParam<bool> {};

TEST_P(PostgresOfAKilledTestTest, EndsWithTheTestProcess) {
  const bool frozen = GetParam();
  GTEST_FLAG_SET(death_test_style, "threadsafe");  // a fresh process, not a fork of this one
  const std::string record = DeathTestRecordPath();
  EXPECT_EXIT(
      {
        std::unique_ptr<PostgresInstance> postgres = StartOrFail();
        if (postgres == nullptr) _exit(1);
        const Connection idle = Connect(postgres->uri(), 60);
        if (!Connected(idle)) _exit(2);
        if (frozen && !postgres->Freeze().ok()) _exit(3);
        std::ofstream(record) << postgres->pid() << " " << postgres->directory() << "\n";
        raise(SIGKILL);
      },
      ::testing::KilledBySignal(SIGKILL), "");
  pid_t postmaster = -1;
  std::string directory;
  std::ifstream(record) >> postmaster >> directory;
  ASSERT_GT(postmaster, 0) << "the child test wrote no record";
  std::filesystem::remove(record);
  const std::string name = std::filesystem::path(directory).filename();
  const absl::Time died = absl::Now();  // about: the child test has just been reaped
  EXPECT_TRUE(WaitUntil([&] {
    return ProcessesWithCommandLineContaining(name).empty() && !std::filesystem::exists(directory);
  })) << "still running: "
      << Pids(ProcessesWithCommandLineContaining(name));
  std::cout << "PostgreSQL and its directory were gone " << absl::FormatDuration(absl::Now() - died)
            << " after the test process died\n";
  std::error_code ignored;
  std::filesystem::remove_all(directory, ignored);  // if the guard failed to
}

INSTANTIATE_TEST_SUITE_P(Frozen, PostgresOfAKilledTestTest, ::testing::Bool(),
                         [](const ::testing::TestParamInfo<bool>& frozen) {
                           return frozen.param ? "Frozen" : "Running";
                         });

}  // namespace
}  // namespace ispq::testing
