#include "tests/integration/server_process.h"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <stdlib.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "absl/status/status.h"
#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/strip.h"
#include "absl/time/clock.h"

extern char** environ;

namespace ispq::testing {
namespace {

std::string ReadWholeFile(const std::string& path) {
  std::ifstream in(path);
  std::stringstream contents;
  contents << in.rdbuf();
  return contents.str();
}

std::string MakeTemporaryDirectory() {
  const char* base = getenv("TMPDIR");
  std::string pattern = absl::StrCat(base != nullptr ? base : "/tmp", "/ispq-server-XXXXXX");
  if (mkdtemp(pattern.data()) == nullptr) return "";
  return pattern;
}

}  // namespace

std::string ServerBinaryPath() {
  // Another build of the server (e.g. to measure a change against the previous one).
  const char* other = getenv("ISPQ_SERVER_BINARY");
  return other != nullptr && *other != '\0' ? other : ISPQ_SERVER_PATH;
}

absl::StatusOr<std::unique_ptr<ServerProcess>> ServerProcess::Start(
    const std::string& server_binary, const std::vector<std::string>& flags,
    absl::Duration timeout) {
  std::unique_ptr<ServerProcess> server(new ServerProcess());
  server->directory_ = MakeTemporaryDirectory();
  if (server->directory_.empty()) return absl::InternalError("mkdtemp failed");
  const std::string port_file = server->directory_ + "/port";
  const std::string log_file = server->directory_ + "/server.log";

  std::vector<std::string> arguments = {server_binary, "--listen=127.0.0.1:0",
                                        "--port_file=" + port_file};
  arguments.insert(arguments.end(), flags.begin(), flags.end());
  std::vector<char*> argv;
  for (std::string& argument : arguments) argv.push_back(argument.data());
  argv.push_back(nullptr);

  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log_file.c_str(),
                                   O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  // The child starts with no blocked signals, whatever the test process blocks.
  posix_spawnattr_t attributes;
  posix_spawnattr_init(&attributes);
  sigset_t no_signals;
  sigemptyset(&no_signals);
  posix_spawnattr_setsigmask(&attributes, &no_signals);
  posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETSIGMASK);
  const int spawned = posix_spawn(&server->pid_, server_binary.c_str(), &actions, &attributes,
                                  argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  posix_spawnattr_destroy(&attributes);
  if (spawned != 0) {
    return absl::InternalError(
        absl::StrCat("cannot start ", server_binary, ": ", std::strerror(spawned)));
  }

  const absl::Time deadline = absl::Now() + timeout;
  while (absl::Now() < deadline) {
    if (!server->running()) {
      server->start_failed_ = true;
      return absl::InternalError(absl::StrCat(
          "the server exited with code ", server->exit_code_.value_or(-1), ":\n", server->Log()));
    }
    if (std::filesystem::exists(port_file)) {
      const std::string text = ReadWholeFile(port_file);
      if (absl::SimpleAtoi(absl::StripAsciiWhitespace(text), &server->port_) && server->port_ > 0) {
        return server;
      }
    }
    absl::SleepFor(absl::Milliseconds(20));
  }
  return absl::DeadlineExceededError(absl::StrCat(
      "the server did not listen within ", absl::FormatDuration(timeout), ":\n", server->Log()));
}

ServerProcess::~ServerProcess() {
  // A server that died on its own explains itself in the test output.
  if (pid_ > 0 && !running() && exit_code_ != 0 && !start_failed_) {
    std::cerr << "ispq-server exited with code " << *exit_code_ << "; its log:\n" << Log();
  }
  if (pid_ > 0 && running()) {
    kill(pid_, SIGKILL);
    WaitForExit(absl::Seconds(30));
  }
  std::error_code ignored;
  if (!directory_.empty()) std::filesystem::remove_all(directory_, ignored);
}

std::string ServerProcess::address() const { return absl::StrCat("127.0.0.1:", port_); }

void ServerProcess::Signal(int signal_number) const {
  if (pid_ > 0) kill(pid_, signal_number);
}

bool ServerProcess::running() {
  if (exit_code_.has_value()) return false;
  int status = 0;
  const pid_t result = waitpid(pid_, &status, WNOHANG);
  if (result == 0) return true;
  exit_code_ = (result == pid_ && WIFEXITED(status)) ? WEXITSTATUS(status) : -1;
  return false;
}

std::optional<int> ServerProcess::WaitForExit(absl::Duration timeout) {
  const absl::Time deadline = absl::Now() + timeout;
  while (running()) {
    if (absl::Now() >= deadline) return std::nullopt;
    absl::SleepFor(absl::Milliseconds(20));
  }
  return exit_code_;
}

bool ServerProcess::WaitForLog(const std::string& text, absl::Duration timeout) const {
  const absl::Time deadline = absl::Now() + timeout;
  while (Log().find(text) == std::string::npos) {
    if (absl::Now() >= deadline) return false;
    absl::SleepFor(absl::Milliseconds(20));
  }
  return true;
}

std::string ServerProcess::Log() const { return ReadWholeFile(directory_ + "/server.log"); }

}  // namespace ispq::testing
