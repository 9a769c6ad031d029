// SPDX-License-Identifier: Apache-2.0
// Starting the long-lived processes a test needs (servers, databases) so that they die with the
// test process however it ends: a normal exit, a failed assertion's abort, a crash, or SIGKILL
// (e.g. ctest's timeout). Each child asks the kernel for a signal when its parent dies
// (prctl(PR_SET_PDEATHSIG)), so no server is left running to hold ports, memory or cores that
// later tests need (after one failed run, 32 ispq-server processes were left behind).
//
// Linux sends that signal when the *thread* that forked the child exits, not when the process
// does. StartChildProcess therefore forks on a thread that lives as long as the process: the
// main thread when called from it, otherwise one launcher thread started for the purpose. Any
// thread may start children, and a short-lived thread's children outlive the thread.
//
// The signal reaches the child only, not what the child starts in turn: a program with children
// of its own (PostgreSQL) runs under tests/support/process_guard_main.cc.
//
// Also: waiting for a child with a bound, and looking at processes the way the fault tests need
// (is it still there, is it stopped, what are its children).
#ifndef ISPQ_TESTS_SUPPORT_CHILD_PROCESS_H_
#define ISPQ_TESTS_SUPPORT_CHILD_PROCESS_H_

#include <signal.h>
#include <sys/types.h>

#include <optional>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "absl/time/time.h"

namespace ispq::testing {

// Whom a child runs as, e.g. PostgreSQL's own unprivileged user when the tests run as root.
struct Credentials {
  uid_t uid = 0;
  gid_t gid = 0;
};

// The credentials of the system user `name` (NotFound if there is none).
absl::StatusOr<Credentials> UserCredentials(const std::string& name);

struct ChildProcessOptions {
  // argv[0] is the program's path; the PATH is not searched.
  std::vector<std::string> argv;
  // stdout and stderr are appended to this file (created if needed); /dev/null if empty. stdin is
  // always /dev/null.
  std::string output_path;
  // What the child receives when the test process dies. A program's own orderly-exit signal
  // (e.g. SIGQUIT for PostgreSQL) lets it clean up; SIGKILL cannot be caught or delayed.
  int death_signal = SIGKILL;
  // Switched to in the child before exec (as root). The death signal is requested after the
  // switch, since changing credentials clears it; this is also why the child does not go
  // through su or runuser.
  std::optional<Credentials> run_as;
};

// Forks and execs the child as described above. Fails if fork or exec fails (the reason is
// reported here, not in the child's output).
absl::StatusOr<pid_t> StartChildProcess(const ChildProcessOptions& options);

// How a child of this process ended (as waitpid reports it), or nullopt if it still runs at
// `timeout`. Reaps the child.
std::optional<int> WaitForChild(pid_t pid, absl::Duration timeout);
// The same without waiting: nullopt while it runs.
std::optional<int> PollChild(pid_t pid);

// Whether `pid` names a live process: not an exited one, not a zombie.
bool ProcessIsAlive(pid_t pid);
// Whether `pid` is stopped (SIGSTOP): state T in /proc.
bool ProcessIsStopped(pid_t pid);
// The live children of `pid`.
std::vector<pid_t> ChildrenOf(pid_t pid);
// The live processes (other than this one) whose command line contains `text`. A process that
// sets its title (a PostgreSQL backend) shows the title.
std::vector<pid_t> ProcessesWithCommandLineContaining(const std::string& text);

// Whether something accepts TCP connections on 127.0.0.1:`port`. A connection only the kernel
// accepts (the listener is stopped) counts: it is in the listen backlog.
bool LoopbackPortAcceptsConnections(int port);

}  // namespace ispq::testing

#endif  // ISPQ_TESTS_SUPPORT_CHILD_PROCESS_H_
