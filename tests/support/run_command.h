// SPDX-License-Identifier: Apache-2.0
// Running the product's binaries from tests, as a user or a script would: short commands (the
// CLI against a test's server, psql, openssl) that end on their own. They are not tied to the
// test's life (a shell's children would not inherit that anyway): a command that outlives a
// killed test ends when its server, which is tied to it (child_process.h), goes. Long-lived
// processes go through tests/support/child_process.h.
#ifndef ISPQ_TESTS_SUPPORT_RUN_COMMAND_H_
#define ISPQ_TESTS_SUPPORT_RUN_COMMAND_H_

#include <string>

namespace ispq::testing {

struct CommandResult {
  int exit_code;       // -1 if the process did not exit normally
  std::string output;  // stdout followed by stderr, interleaved as written
};

// Runs `command_line` through /bin/sh with stderr merged into stdout.
CommandResult RunCommand(const std::string& command_line);

}  // namespace ispq::testing

#endif  // ISPQ_TESTS_SUPPORT_RUN_COMMAND_H_
