// SPDX-License-Identifier: Apache-2.0
#include "tests/support/child_process.h"

#include <arpa/inet.h>
#include <fcntl.h>
#include <grp.h>
#include <netinet/in.h>
#include <poll.h>
#include <pwd.h>
#include <sys/prctl.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <deque>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <thread>

#include "absl/base/thread_annotations.h"
#include "absl/status/status.h"
#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"
#include "absl/synchronization/mutex.h"
#include "absl/synchronization/notification.h"
#include "absl/time/clock.h"

namespace ispq::testing {
namespace {

// Everything the child needs, made before fork: between fork and exec a child of a threaded
// process may only make async-signal-safe calls (no allocation, no locks).
struct PreparedChild {
  explicit PreparedChild(const ChildProcessOptions& options) : options(options) {
    for (const std::string& argument : options.argv) argv.push_back(argument.c_str());
    argv.push_back(nullptr);
    output = options.output_path.empty() ? "/dev/null" : options.output_path.c_str();
  }
  const ChildProcessOptions& options;
  std::vector<const char*> argv;
  const char* output;
};

// What the child reports through the pipe when it cannot exec.
struct ChildFailure {
  const char* stage;  // a string literal: the same address in parent and child
  int error;
};

// Reports `stage` and errno to the parent and exits; async-signal-safe.
[[noreturn]] void FailInChild(int report_fd, const char* stage) {
  const ChildFailure failure{stage, errno};
  [[maybe_unused]] const ssize_t written = write(report_fd, &failure, sizeof(failure));
  _exit(127);
}

// The child's side of fork, up to exec. `parent` is the pid of the process that forked.
[[noreturn]] void BecomeChild(const PreparedChild& child, pid_t parent, int report_fd) {
  const ChildProcessOptions& options = child.options;
  const int input = open("/dev/null", O_RDONLY);
  const int output = open(child.output, O_WRONLY | O_CREAT | O_APPEND, 0644);
  if (input < 0 || output < 0) FailInChild(report_fd, "open");
  if (dup2(input, STDIN_FILENO) < 0 || dup2(output, STDOUT_FILENO) < 0 ||
      dup2(output, STDERR_FILENO) < 0) {
    FailInChild(report_fd, "dup2");
  }
  // Nothing else of the test's is inherited (e.g. the pipe a gtest death test's parent reads
  // until every holder has closed it). Best effort: a kernel before 5.11 leaves them open.
  close_range(3, ~0U, CLOSE_RANGE_CLOEXEC);
  if (options.run_as.has_value()) {
    const gid_t gid = options.run_as->gid;
    if (setgroups(1, &gid) != 0 || setgid(gid) != 0 || setuid(options.run_as->uid) != 0) {
      FailInChild(report_fd, "dropping privileges");
    }
  }
  // After the credentials change, which would clear it.
  if (prctl(PR_SET_PDEATHSIG, options.death_signal) != 0) FailInChild(report_fd, "prctl");
  // The parent may have died before the request: then nobody will send the signal.
  if (getppid() != parent) _exit(126);
  // The child starts with no blocked signals, whatever the test process blocks.
  sigset_t no_signals;
  sigemptyset(&no_signals);
  sigprocmask(SIG_SETMASK, &no_signals, nullptr);
  execv(child.argv[0], const_cast<char* const*>(child.argv.data()));
  FailInChild(report_fd, "exec");
}

// Forks on the calling thread; the child is tied to this thread's life (see the header).
absl::StatusOr<pid_t> ForkHere(const PreparedChild& child) {
  int report[2];
  if (pipe2(report, O_CLOEXEC) != 0) return absl::InternalError("pipe2 failed");
  const pid_t parent = getpid();
  const pid_t pid = fork();
  if (pid == 0) BecomeChild(child, parent, report[1]);
  close(report[1]);
  if (pid < 0) {
    close(report[0]);
    return absl::InternalError(absl::StrCat("fork failed: ", std::strerror(errno)));
  }
  // Closed by exec (O_CLOEXEC): nothing to read means the program runs.
  ChildFailure failure{};
  ssize_t got;
  do {
    got = read(report[0], &failure, sizeof(failure));
  } while (got < 0 && errno == EINTR);
  close(report[0]);
  if (got <= 0) return pid;
  waitpid(pid, nullptr, 0);
  return absl::InternalError(absl::StrCat("cannot start ", child.argv[0], ": ", failure.stage,
                                          " failed: ", std::strerror(failure.error)));
}

// A thread that lives as long as the process and forks for the threads that may not.
class Launcher {
 public:
  // The launcher of this process (a forked copy of the process gets its own).
  static Launcher& OfThisProcess() {
    static absl::Mutex mutex(absl::kConstInit);
    static Launcher* launcher = nullptr;
    static pid_t owner = 0;
    absl::MutexLock lock(&mutex);
    if (launcher == nullptr || owner != getpid()) {
      launcher = new Launcher();  // never deleted: the thread runs until the process ends
      owner = getpid();
    }
    return *launcher;
  }

  absl::StatusOr<pid_t> Fork(const PreparedChild& child) {
    // Shared: the launcher may still be leaving Notify() when the caller wakes up.
    auto request = std::make_shared<Request>(&child);
    {
      absl::MutexLock lock(&mutex_);
      requests_.push_back(request);
    }
    request->done.WaitForNotification();
    return request->result;
  }

 private:
  struct Request {
    explicit Request(const PreparedChild* child) : child(child) {}
    const PreparedChild* child;
    absl::StatusOr<pid_t> result = absl::UnknownError("not run");
    absl::Notification done;
  };

  Launcher() {
    std::thread([this] { Serve(); }).detach();
  }

  [[noreturn]] void Serve() {
    while (true) {
      std::shared_ptr<Request> request;
      {
        absl::MutexLock lock(&mutex_, absl::Condition(this, &Launcher::HasRequests));
        request = requests_.front();
        requests_.pop_front();
      }
      request->result = ForkHere(*request->child);
      request->done.Notify();
    }
  }
  bool HasRequests() const ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_) { return !requests_.empty(); }

  absl::Mutex mutex_;
  std::deque<std::shared_ptr<Request>> requests_ ABSL_GUARDED_BY(mutex_);
};

bool OnMainThread() { return gettid() == getpid(); }

// Fields of /proc/<pid>/stat after the command name: [0] is the state, [1] the parent.
std::vector<std::string> StatFields(pid_t pid) {
  std::ifstream in(absl::StrCat("/proc/", pid, "/stat"));
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const size_t name_end = text.rfind(')');  // the name may contain spaces and parentheses
  if (name_end == std::string::npos) return {};
  std::istringstream rest(text.substr(name_end + 1));
  std::vector<std::string> fields;
  for (std::string field; rest >> field && fields.size() < 2;) fields.push_back(field);
  return fields;
}

bool IsLiveState(const std::string& state) { return state != "Z" && state != "X"; }

std::vector<pid_t> AllProcesses() {
  std::vector<pid_t> pids;
  std::error_code error;
  for (const auto& entry : std::filesystem::directory_iterator("/proc", error)) {
    pid_t pid = 0;
    if (absl::SimpleAtoi(entry.path().filename().string(), &pid)) pids.push_back(pid);
  }
  return pids;
}

}  // namespace

absl::StatusOr<Credentials> UserCredentials(const std::string& name) {
  passwd entry;
  passwd* found = nullptr;
  std::vector<char> buffer(16384);
  if (getpwnam_r(name.c_str(), &entry, buffer.data(), buffer.size(), &found) != 0 ||
      found == nullptr) {
    return absl::NotFoundError(absl::StrCat("no user ", name));
  }
  return Credentials{found->pw_uid, found->pw_gid};
}

absl::StatusOr<pid_t> StartChildProcess(const ChildProcessOptions& options) {
  if (options.argv.empty()) return absl::InvalidArgumentError("no program to start");
  const PreparedChild child(options);
  if (OnMainThread()) return ForkHere(child);
  return Launcher::OfThisProcess().Fork(child);
}

std::optional<int> PollChild(pid_t pid) {
  int status = 0;
  pid_t result;
  do {
    result = waitpid(pid, &status, WNOHANG);
  } while (result < 0 && errno == EINTR);
  if (result == 0) return std::nullopt;
  // Not our child (any more): report it as killed, it is gone either way.
  if (result < 0) return W_EXITCODE(0, SIGKILL);
  return status;
}

std::optional<int> WaitForChild(pid_t pid, absl::Duration timeout) {
  const absl::Time deadline = absl::Now() + timeout;
  while (true) {
    if (std::optional<int> status = PollChild(pid)) return status;
    if (absl::Now() >= deadline) return std::nullopt;
    absl::SleepFor(absl::Milliseconds(10));
  }
}

bool ProcessIsAlive(pid_t pid) {
  const std::vector<std::string> fields = StatFields(pid);
  return !fields.empty() && IsLiveState(fields[0]);
}

bool ProcessIsStopped(pid_t pid) {
  const std::vector<std::string> fields = StatFields(pid);
  return !fields.empty() && fields[0] == "T";
}

std::vector<pid_t> ChildrenOf(pid_t parent) {
  std::vector<pid_t> children;
  for (pid_t pid : AllProcesses()) {
    const std::vector<std::string> fields = StatFields(pid);
    if (fields.size() == 2 && IsLiveState(fields[0]) && fields[1] == absl::StrCat(parent)) {
      children.push_back(pid);
    }
  }
  return children;
}

std::vector<pid_t> ProcessesWithCommandLineContaining(const std::string& text) {
  std::vector<pid_t> found;
  for (pid_t pid : AllProcesses()) {
    if (pid == getpid()) continue;  // the test itself may well name the text
    std::ifstream in(absl::StrCat("/proc/", pid, "/cmdline"));
    std::string command((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (command.find(text) != std::string::npos && ProcessIsAlive(pid)) found.push_back(pid);
  }
  return found;
}

bool LoopbackPortAcceptsConnections(int port) {
  const int fd = socket(AF_INET, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  if (fd < 0) return false;
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  address.sin_port = htons(port);
  bool accepted = connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof(address)) == 0;
  if (!accepted && errno == EINPROGRESS) {
    // Loopback answers at once unless the listener's backlog is full: then it is there.
    pollfd wait{fd, POLLOUT, 0};
    int error = 0;
    socklen_t length = sizeof(error);
    accepted = poll(&wait, 1, 1000) == 0 ||
               (getsockopt(fd, SOL_SOCKET, SO_ERROR, &error, &length) == 0 && error == 0);
  }
  close(fd);
  return accepted;
}

}  // namespace ispq::testing
