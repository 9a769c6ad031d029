// SPDX-License-Identifier: Apache-2.0
// ispq_process_guard: runs one program for a test (PostgreSQL's postmaster) and makes sure that
// nothing it started outlives it or the test.
//
//   ispq_process_guard [--remove_when_orphaned=DIR] -- PROGRAM [ARGS...]
//
// Why a process of its own: PostgreSQL's backends each call setsid(), so neither a process group
// nor the parent-death signal reaches all of them, and a backend stopped by SIGSTOP (a test's
// frozen database) stays stopped forever once its postmaster is gone, since nothing would send it
// SIGCONT or SIGKILL. The guard is a child subreaper (PR_SET_CHILD_SUBREAPER): whatever its
// program leaves behind becomes its own child, which it can always kill and reap.
//
// - When PROGRAM exits, the guard kills (SIGKILL) whatever is left of its descendants, reaps
//   them, and exits with PROGRAM's exit code (128 + the signal if it was killed).
// - On SIGTERM, SIGINT or SIGHUP (the test process starts the guard with SIGTERM as its
//   parent-death signal, so this is what a dead test sends): every descendant is continued
//   (a frozen database thaws), PROGRAM gets SIGQUIT (PostgreSQL's immediate shutdown, which ends
//   its backends and removes its shared memory) and a bounded time to exit, then whatever is
//   left is killed, and DIR (the cluster's directory) is removed.
//
// PROGRAM is asked for SIGKILL if the guard itself dies (e.g. killed with SIGKILL).
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

namespace {

// PostgreSQL itself SIGKILLs children that ignore an immediate shutdown for 5 s.
constexpr std::chrono::seconds kShutdownTime(15);

struct Arguments {
  std::string remove_when_orphaned;
  std::vector<char*> program;  // null-terminated
};

bool ParseArguments(int argc, char** argv, Arguments& arguments) {
  constexpr std::string_view kRemove = "--remove_when_orphaned=";
  int i = 1;
  for (; i < argc && std::string_view(argv[i]) != "--"; ++i) {
    const std::string_view argument = argv[i];
    if (!argument.starts_with(kRemove)) return false;
    arguments.remove_when_orphaned = argument.substr(kRemove.size());
  }
  for (++i; i < argc; ++i) arguments.program.push_back(argv[i]);
  if (arguments.program.empty()) return false;
  arguments.program.push_back(nullptr);
  return true;
}

// The parent of every live process, from /proc.
std::map<pid_t, pid_t> ParentsOfAllProcesses() {
  std::map<pid_t, pid_t> parents;
  std::error_code error;
  for (const auto& entry : std::filesystem::directory_iterator("/proc", error)) {
    const std::string name = entry.path().filename().string();
    if (name.find_first_not_of("0123456789") != std::string::npos) continue;
    std::ifstream in(entry.path() / "stat");
    const std::string stat((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const size_t name_end = stat.rfind(')');
    if (name_end == std::string::npos) continue;
    std::istringstream rest(stat.substr(name_end + 1));
    std::string state;
    pid_t parent = 0;
    if (rest >> state >> parent) parents[std::stoi(name)] = parent;
  }
  return parents;
}

// Every process below this one: its children, theirs, and so on.
std::vector<pid_t> Descendants() {
  const std::map<pid_t, pid_t> parents = ParentsOfAllProcesses();
  std::vector<pid_t> found = {getpid()};
  for (size_t next = 0; next < found.size(); ++next) {
    for (const auto& [pid, parent] : parents) {
      if (parent == found[next]) found.push_back(pid);
    }
  }
  found.erase(found.begin());
  return found;
}

void SignalDescendants(int signal_number) {
  for (pid_t pid : Descendants()) kill(pid, signal_number);
}

// Reaps every child that has ended; whether `program` was among them (its status then).
bool ReapEnded(pid_t program, int& program_status) {
  bool program_ended = false;
  int status = 0;
  for (pid_t pid; (pid = waitpid(-1, &status, WNOHANG)) > 0;) {
    if (pid == program) {
      program_status = status;
      program_ended = true;
    }
  }
  return program_ended;
}

// Kills whatever is left below and reaps it; orphans of the program are this process's children.
void KillEverythingLeft() {
  for (std::vector<pid_t> left = Descendants(); !left.empty(); left = Descendants()) {
    for (pid_t pid : left) kill(pid, SIGKILL);
    for (pid_t pid : left) waitpid(pid, nullptr, 0);  // not ours (yet): returns at once
    timespec pause{0, 10'000'000};
    nanosleep(&pause, nullptr);
  }
  while (waitpid(-1, nullptr, WNOHANG) > 0) {
  }
}

int ExitCodeOf(int status) {
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

// The test is gone: thaw, shut down, clean up.
int ShutDown(pid_t program, const sigset_t& signals, const std::string& remove) {
  SignalDescendants(SIGCONT);
  kill(program, SIGQUIT);
  int status = 0;
  const auto deadline = std::chrono::steady_clock::now() + kShutdownTime;
  const timespec tick{0, 100'000'000};
  while (!ReapEnded(program, status) && std::chrono::steady_clock::now() < deadline) {
    sigtimedwait(&signals, nullptr, &tick);
  }
  KillEverythingLeft();
  if (!remove.empty()) {
    std::error_code ignored;
    std::filesystem::remove_all(remove, ignored);
  }
  return 0;
}

[[noreturn]] void RunProgram(const Arguments& arguments, pid_t guard) {
  prctl(PR_SET_PDEATHSIG, SIGKILL);
  if (getppid() != guard) _exit(126);
  sigset_t none;
  sigemptyset(&none);
  sigprocmask(SIG_SETMASK, &none, nullptr);
  execv(arguments.program[0], arguments.program.data());
  std::fprintf(stderr, "ispq_process_guard: cannot run %s: %s\n", arguments.program[0],
               std::strerror(errno));
  _exit(127);
}

}  // namespace

int main(int argc, char** argv) {
  Arguments arguments;
  if (!ParseArguments(argc, argv, arguments)) {
    std::fprintf(stderr, "usage: %s [--remove_when_orphaned=DIR] -- PROGRAM [ARGS...]\n", argv[0]);
    return 2;
  }
  if (prctl(PR_SET_CHILD_SUBREAPER, 1) != 0) {
    std::perror("ispq_process_guard: PR_SET_CHILD_SUBREAPER");
    return 1;
  }
  // Handled synchronously below (sigwaitinfo), so blocked from now on.
  sigset_t signals;
  sigemptyset(&signals);
  for (int signal_number : {SIGCHLD, SIGTERM, SIGINT, SIGHUP}) sigaddset(&signals, signal_number);
  sigprocmask(SIG_BLOCK, &signals, nullptr);

  const pid_t guard = getpid();
  const pid_t program = fork();
  if (program < 0) {
    std::perror("ispq_process_guard: fork");
    return 1;
  }
  if (program == 0) RunProgram(arguments, guard);

  while (true) {
    siginfo_t info;
    if (sigwaitinfo(&signals, &info) < 0) continue;
    if (info.si_signo != SIGCHLD) {
      return ShutDown(program, signals, arguments.remove_when_orphaned);
    }
    int status = 0;
    if (ReapEnded(program, status)) {
      KillEverythingLeft();
      return ExitCodeOf(status);
    }
  }
}
