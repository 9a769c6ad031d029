// SPDX-License-Identifier: Apache-2.0
// A real PostgreSQL server for tests, from Debian's `postgresql` package: a fresh cluster
// (initdb) in a temporary directory, its `postgres` binary run directly as a child of the test
// (not through pg_ctl, which detaches it) on a free loopback port, trust authentication for the
// one test user, fsync off. Commits are still written to the operating system before they are
// acknowledged (synchronous_commit stays on), so a committed row survives Stop(kImmediate);
// only a crash of the machine itself could lose it.
//
// The server dies with the test process however the test ends, a crash or SIGKILL included,
// frozen or not: the postmaster runs under tests/support/process_guard_main.cc, which the test
// process starts with a parent-death signal (tests/support/child_process.h). When the test dies,
// the guard thaws the instance, shuts it down (immediate mode), kills whatever is left and
// removes the directory. As root (CI) the cluster, guard included, runs as the package's
// unprivileged `postgres` user, since PostgreSQL refuses to run as root.
//
// A fault suite can make the whole database misbehave: Freeze() hangs it without closing a
// connection, Stop() and Restart() make an outage of a chosen length on the same port and data.
// Every process of the instance has the directory's name in its command line (the postmaster's
// arguments, and cluster_name in every backend's process title), so a test can check that none
// is left.
//
// Every wait is bounded; the destructor stops whatever runs (a frozen instance too) and removes
// the directory.
#ifndef ISPQ_TESTS_SUPPORT_POSTGRES_INSTANCE_H_
#define ISPQ_TESTS_SUPPORT_POSTGRES_INSTANCE_H_

#include <sys/types.h>

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "tests/support/child_process.h"

namespace ispq::testing {

class PostgresInstance {
 public:
  // How Stop shuts the server down (PostgreSQL's own shutdown modes).
  enum class StopMode {
    kFast,       // SIGINT: sessions are ended, a checkpoint is written
    kImmediate,  // SIGQUIT: every process quits at once, as in a crash; restart recovers
  };

  // Fails with the commands' output if PostgreSQL is not installed or does not start.
  static absl::StatusOr<std::unique_ptr<PostgresInstance>> Start();
  ~PostgresInstance();
  PostgresInstance(const PostgresInstance&) = delete;
  PostgresInstance& operator=(const PostgresInstance&) = delete;

  // postgresql://ispq@127.0.0.1:<port>/<database>; the same across Stop and Restart.
  std::string uri(const std::string& database = "postgres") const;
  // A new empty database, for a test that needs a store of its own.
  absl::StatusOr<std::string> CreateDatabase(const std::string& name);
  // Runs one SQL command with psql; its output.
  absl::StatusOr<std::string> Sql(const std::string& sql, const std::string& database = "postgres");

  // SIGSTOP to every process of the instance, the postmaster first (so that it starts no new
  // backend) and then each of its children: open connections stay open and unanswered, and new
  // ones are accepted by the kernel but never answered. Returns once every process is stopped.
  // FailedPrecondition if not running.
  absl::Status Freeze();
  // SIGCONT to every process of the instance: all of it goes on where it stopped. Nothing to do
  // if not frozen.
  absl::Status Thaw();

  // Shuts the server down (thawing it first if frozen) and returns once none of its processes is
  // left and nothing listens on its port: connecting is refused until Restart. If it does not
  // shut down in time, its processes are killed and the status says so. Nothing to do if it is
  // not running.
  absl::Status Stop(StopMode mode = StopMode::kFast);
  // Starts the server again on the same data directory and port (stopping it first, kFast, if it
  // runs) and returns once it accepts connections. Fails if it does not start in time, e.g.
  // because another process took the port meanwhile.
  absl::Status Restart();

  bool running() const { return postmaster_ > 0; }
  bool frozen() const { return frozen_; }
  // The postmaster's pid (its children are the backends); -1 while stopped.
  pid_t pid() const { return postmaster_; }
  int port() const { return port_; }
  // The instance's temporary directory: data/ (the cluster), log (the server's log). Its name
  // is in the command line of every process of the instance.
  const std::string& directory() const { return directory_; }
  // What the server logged so far, for failure messages.
  std::string Log() const;

 private:
  PostgresInstance() = default;

  // Creates the cluster in directory_/data.
  absl::Status InitializeCluster();
  // Starts the postmaster on port_ and waits until it accepts connections.
  absl::Status Launch();
  // Until the postmaster accepts connections, or fails if it exits or the wait runs out.
  absl::Status WaitUntilReady();
  // Waits for the guard, after the postmaster was told to end: true if it ended in time.
  bool WaitForGuard();
  // The postmaster and its children.
  std::vector<pid_t> Processes() const;

  std::string directory_;
  std::string bin_;
  std::optional<Credentials> run_as_;  // the cluster's owner when the tests run as root
  int port_ = 0;
  pid_t guard_ = -1;  // the postmaster's parent, a child of this process
  pid_t postmaster_ = -1;
  bool frozen_ = false;
};

}  // namespace ispq::testing

#endif  // ISPQ_TESTS_SUPPORT_POSTGRES_INSTANCE_H_
