// SPDX-License-Identifier: Apache-2.0
#include "tests/integration/server_process.h"

#include <signal.h>
#include <stdlib.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "absl/status/status.h"
#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/strip.h"
#include "absl/time/clock.h"
#include "tests/support/child_process.h"

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

  ChildProcessOptions child;
  child.argv = {server_binary, "--listen=127.0.0.1:0", "--port_file=" + port_file};
  child.argv.insert(child.argv.end(), flags.begin(), flags.end());
  child.output_path = log_file;
  child.death_signal = SIGKILL;  // a crashed test's server has nobody left to drain for
  absl::StatusOr<pid_t> pid = StartChildProcess(child);
  if (!pid.ok()) return pid.status();
  server->pid_ = *pid;

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
  const std::optional<int> status = PollChild(pid_);
  if (!status.has_value()) return true;
  exit_code_ = WIFEXITED(*status) ? WEXITSTATUS(*status) : -1;
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
