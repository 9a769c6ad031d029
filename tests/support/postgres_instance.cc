// SPDX-License-Identifier: Apache-2.0
#include "tests/support/postgres_instance.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <vector>

#include "absl/status/status.h"
#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"
#include "absl/time/clock.h"
#include "absl/time/time.h"
#include "tests/support/bounded_wait.h"
#include "tests/support/run_command.h"

namespace ispq::testing {
namespace {

// Bounds that only stop a hung start or stop from hanging the test: a loaded machine may need a
// while, and the test's own timeout is the real bound.
constexpr absl::Duration kStartTimeout = absl::Seconds(120);
constexpr absl::Duration kStopTimeout = absl::Seconds(60);

// A port nobody listens on right now (the kernel's pick for port 0).
int FreeLoopbackPort() {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  address.sin_port = 0;
  socklen_t length = sizeof(address);
  int port = 0;
  if (bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof(address)) == 0 &&
      getsockname(fd, reinterpret_cast<sockaddr*>(&address), &length) == 0) {
    port = ntohs(address.sin_port);
  }
  close(fd);
  return port;
}

// The newest installed PostgreSQL's bin directory, e.g. /usr/lib/postgresql/15/bin.
std::string PostgresBinDirectory() {
  const CommandResult found =
      RunCommand("ls -d /usr/lib/postgresql/*/bin 2>/dev/null | sort -V | tail -n 1");
  std::string bin = found.output;
  while (!bin.empty() && (bin.back() == '\n' || bin.back() == ' ')) bin.pop_back();
  return bin;
}

std::string ReadFile(const std::string& path) {
  std::ifstream in(path);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// Runs a short-lived program to its end (it too dies with the test); its exit code, or -1 if it
// was killed or ran out of `timeout` (then it is killed).
int RunToEnd(const ChildProcessOptions& options, absl::Duration timeout) {
  const absl::StatusOr<pid_t> pid = StartChildProcess(options);
  if (!pid.ok()) return -1;
  std::optional<int> status = WaitForChild(*pid, timeout);
  if (!status.has_value()) {
    kill(*pid, SIGKILL);
    status = WaitForChild(*pid, kStopTimeout);
  }
  return status.has_value() && WIFEXITED(*status) ? WEXITSTATUS(*status) : -1;
}

}  // namespace

absl::StatusOr<std::unique_ptr<PostgresInstance>> PostgresInstance::Start() {
  std::unique_ptr<PostgresInstance> instance(new PostgresInstance());
  instance->bin_ = PostgresBinDirectory();
  if (instance->bin_.empty()) {
    return absl::FailedPreconditionError(
        "PostgreSQL is not installed: run deploy/install-deps.sh (package postgresql)");
  }
  char pattern[] = "/tmp/ispq-postgres-XXXXXX";
  if (mkdtemp(pattern) == nullptr) return absl::InternalError("mkdtemp failed");
  instance->directory_ = pattern;
  if (geteuid() == 0) {
    // PostgreSQL refuses to run as root: the package's own unprivileged user owns the cluster.
    absl::StatusOr<Credentials> postgres = UserCredentials("postgres");
    if (!postgres.ok()) return postgres.status();
    instance->run_as_ = *postgres;
    if (chown(pattern, postgres->uid, postgres->gid) != 0) {
      return absl::InternalError(absl::StrCat("cannot give ", pattern, " to postgres"));
    }
  }
  if (absl::Status created = instance->InitializeCluster(); !created.ok()) return created;
  // Another test may take the free port before the server binds it: then try another one.
  absl::Status launched;
  for (int attempt = 0; attempt < 3; ++attempt) {
    instance->port_ = FreeLoopbackPort();
    launched = instance->Launch();
    if (launched.ok()) return instance;
    if (!absl::StrContains(instance->Log(), "could not bind")) break;
  }
  return launched;
}

absl::Status PostgresInstance::InitializeCluster() {
  ChildProcessOptions initdb;
  initdb.argv = {bin_ + "/initdb",
                 "-D",
                 directory_ + "/data",
                 "-U",
                 "ispq",
                 "--auth=trust",
                 "--no-sync",
                 "-E",
                 "UTF8",
                 "--locale=C.UTF-8"};
  initdb.output_path = directory_ + "/initdb.log";
  initdb.run_as = run_as_;
  if (RunToEnd(initdb, kStartTimeout) != 0) {
    return absl::InternalError(
        absl::StrCat("initdb failed:\n", ReadFile(directory_ + "/initdb.log")));
  }
  return absl::OkStatus();
}

absl::Status PostgresInstance::Launch() {
  const std::string name = std::filesystem::path(directory_).filename();
  ChildProcessOptions guarded;
  guarded.argv = {ISPQ_PROCESS_GUARD_PATH,
                  "--remove_when_orphaned=" + directory_,
                  "--",
                  bin_ + "/postgres",
                  "-D",
                  directory_ + "/data",
                  "-p",
                  absl::StrCat(port_),
                  "-k",
                  directory_,
                  "-c",
                  "cluster_name=" + name,  // in every backend's process title
                  "-c",
                  "listen_addresses=127.0.0.1",
                  "-c",
                  "fsync=off",
                  "-c",
                  "full_page_writes=off",
                  "-c",
                  "max_connections=300"};
  guarded.output_path = directory_ + "/log";
  guarded.death_signal = SIGTERM;  // the guard's cue to clean up after a dead test
  guarded.run_as = run_as_;
  absl::StatusOr<pid_t> guard = StartChildProcess(guarded);
  if (!guard.ok()) return guard.status();
  guard_ = *guard;
  frozen_ = false;
  // The guard's only child, at once (until the postmaster exits and leaves orphans to it).
  std::vector<pid_t> children;
  WaitUntil([&] { return !(children = ChildrenOf(guard_)).empty() || PollChild(guard_); },
            kStartTimeout);
  postmaster_ = children.empty() ? -1 : children.front();
  absl::Status ready = WaitUntilReady();
  if (!ready.ok() && running()) {
    // Not left half-started.
    kill(postmaster_, SIGKILL);
    WaitForGuard();
  }
  if (!ready.ok()) postmaster_ = guard_ = -1;
  return ready;
}

absl::Status PostgresInstance::WaitUntilReady() {
  ChildProcessOptions probe;
  probe.argv = {
      bin_ + "/pg_isready", "-q", "-h", "127.0.0.1", "-p", absl::StrCat(port_), "-U", "ispq", "-d",
      "postgres",           "-t", "5"};
  const absl::Time deadline = absl::Now() + kStartTimeout;
  while (absl::Now() < deadline) {
    if (std::optional<int> ended = PollChild(guard_); ended.has_value() || postmaster_ < 0) {
      postmaster_ = -1;
      return absl::InternalError(absl::StrCat("postgres exited (wait status ", ended.value_or(-1),
                                              ") while starting; its log:\n", Log()));
    }
    if (RunToEnd(probe, absl::Seconds(30)) == 0) return absl::OkStatus();
    absl::SleepFor(absl::Milliseconds(20));
  }
  return absl::DeadlineExceededError(absl::StrCat("postgres did not accept connections within ",
                                                  absl::FormatDuration(kStartTimeout),
                                                  "; its log:\n", Log()));
}

bool PostgresInstance::WaitForGuard() {
  // The guard exits once the postmaster has, and after it has killed and reaped what was left.
  if (WaitForChild(guard_, kStopTimeout).has_value()) return true;
  kill(postmaster_, SIGKILL);
  WaitForChild(guard_, kStopTimeout);
  return false;
}

std::vector<pid_t> PostgresInstance::Processes() const {
  std::vector<pid_t> processes = ChildrenOf(postmaster_);
  processes.insert(processes.begin(), postmaster_);
  return processes;
}

PostgresInstance::~PostgresInstance() {
  if (running()) {
    const absl::Status stopped = Stop(StopMode::kImmediate);
    if (!stopped.ok()) std::cerr << "stopping PostgreSQL: " << stopped << "\n";
  }
  if (!directory_.empty()) {
    std::error_code ignored;
    std::filesystem::remove_all(directory_, ignored);
  }
}

absl::Status PostgresInstance::Freeze() {
  if (!running()) return absl::FailedPreconditionError("PostgreSQL is not running");
  if (frozen_) return absl::OkStatus();
  frozen_ = true;
  // The postmaster first: once it is stopped, it starts no backend that would be missed.
  kill(postmaster_, SIGSTOP);
  if (!WaitUntil([&] { return ProcessIsStopped(postmaster_); }, kStopTimeout)) {
    return absl::DeadlineExceededError("PostgreSQL's postmaster did not stop");
  }
  for (pid_t backend : ChildrenOf(postmaster_)) kill(backend, SIGSTOP);
  const bool all_stopped = WaitUntil(
      [&] {
        for (pid_t pid : Processes()) {
          if (!ProcessIsStopped(pid)) return false;
        }
        return true;
      },
      kStopTimeout);
  if (!all_stopped) return absl::DeadlineExceededError("PostgreSQL's processes did not all stop");
  return absl::OkStatus();
}

absl::Status PostgresInstance::Thaw() {
  if (!frozen_) return absl::OkStatus();
  for (pid_t pid : Processes()) kill(pid, SIGCONT);
  frozen_ = false;
  return absl::OkStatus();
}

absl::Status PostgresInstance::Stop(StopMode mode) {
  if (!running()) return absl::OkStatus();
  if (absl::Status thawed = Thaw(); !thawed.ok()) return thawed;
  const std::string name = std::filesystem::path(directory_).filename();
  kill(postmaster_, mode == StopMode::kFast ? SIGINT : SIGQUIT);
  absl::Status stopped = absl::OkStatus();
  if (!WaitForGuard()) {
    stopped = absl::DeadlineExceededError(absl::StrCat(
        "PostgreSQL did not shut down within ", absl::FormatDuration(kStopTimeout), "; killed"));
  }
  postmaster_ = guard_ = -1;
  // The guard has reaped everything; this only makes sure, for the callers' sake.
  const bool gone = WaitUntil(
      [&] {
        return ProcessesWithCommandLineContaining(name).empty() &&
               !LoopbackPortAcceptsConnections(port_);
      },
      kStopTimeout);
  if (!gone && stopped.ok()) {
    stopped = absl::InternalError("PostgreSQL's processes outlived its guard");
  }
  return stopped;
}

absl::Status PostgresInstance::Restart() {
  if (absl::Status stopped = Stop(StopMode::kFast); !stopped.ok()) return stopped;
  return Launch();
}

std::string PostgresInstance::Log() const { return ReadFile(directory_ + "/log"); }

std::string PostgresInstance::uri(const std::string& database) const {
  return absl::StrCat("postgresql://ispq@127.0.0.1:", port_, "/", database);
}

absl::StatusOr<std::string> PostgresInstance::Sql(const std::string& sql,
                                                  const std::string& database) {
  const CommandResult result =
      RunCommand(absl::StrCat("timeout 120 ", bin_, "/psql -X -q -t -A -v ON_ERROR_STOP=1 '",
                              uri(database), "' -c \"", sql, "\""));
  if (result.exit_code != 0) {
    return absl::InternalError(absl::StrCat("psql failed: ", sql, "\n", result.output));
  }
  return result.output;
}

absl::StatusOr<std::string> PostgresInstance::CreateDatabase(const std::string& name) {
  absl::StatusOr<std::string> created = Sql(absl::StrCat("CREATE DATABASE ", name));
  if (!created.ok()) return created.status();
  return uri(name);
}

}  // namespace ispq::testing
