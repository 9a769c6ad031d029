// Running the product's binaries from tests, as a user or a script would.
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
