// SPDX-License-Identifier: Apache-2.0
// The real ispq-server binary, started by a test on a free loopback port and stopped by it.
//
// The server listens on 127.0.0.1:0 and writes the port it bound (--port_file), so tests never
// race for ports. Its log (stderr) goes to a file the test can read, e.g. to check the
// structured job lines or to explain a failure. The destructor kills a server still running.
//
// The server dies with the test process however the test ends, a crash or SIGKILL included:
// it is started through tests/support/child_process.h (PR_SET_PDEATHSIG), from a thread that
// lives as long as the process, so any thread may start one, and a server started from a
// short-lived thread outlives that thread.
#ifndef ISPQ_TESTS_INTEGRATION_SERVER_PROCESS_H_
#define ISPQ_TESTS_INTEGRATION_SERVER_PROCESS_H_

#include <sys/types.h>

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "absl/time/time.h"

namespace ispq::testing {

class ServerProcess {
 public:
  // Starts `server_binary` with `flags` (plus --listen and --port_file) and waits until it
  // listens. Fails with the server's log if it exits or does not listen within `timeout` (only
  // a safety net for a hung start: a loaded machine may take a while).
  static absl::StatusOr<std::unique_ptr<ServerProcess>> Start(
      const std::string& server_binary, const std::vector<std::string>& flags,
      absl::Duration timeout = absl::Seconds(300));
  ~ServerProcess();
  ServerProcess(const ServerProcess&) = delete;
  ServerProcess& operator=(const ServerProcess&) = delete;

  int port() const { return port_; }
  std::string address() const;  // "127.0.0.1:<port>"
  pid_t pid() const { return pid_; }
  const std::string& directory() const { return directory_; }

  // Sends `signal_number` (e.g. SIGTERM).
  void Signal(int signal_number) const;
  // Waits for the process to exit; its exit code (-1 if killed by a signal), or nullopt if it
  // is still running at `timeout`.
  std::optional<int> WaitForExit(absl::Duration timeout);
  bool running();

  // Everything the server logged so far.
  std::string Log() const;
  // Whether the log contains `text` within `timeout` (log lines trail the events they report;
  // the default only stops a hang).
  bool WaitForLog(const std::string& text, absl::Duration timeout = absl::Seconds(300)) const;

 private:
  ServerProcess() = default;

  pid_t pid_ = -1;
  int port_ = 0;
  std::string directory_;
  std::optional<int> exit_code_;
  bool start_failed_ = false;  // Start reported the log already
};

// The built server binary (set by CMake), or $ISPQ_SERVER_BINARY if set.
std::string ServerBinaryPath();

}  // namespace ispq::testing

#endif  // ISPQ_TESTS_INTEGRATION_SERVER_PROCESS_H_
