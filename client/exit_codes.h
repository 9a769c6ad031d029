// SPDX-License-Identifier: Apache-2.0
// Exit codes of the `ispq` command line, stable for scripts (also listed in README.md).
#ifndef ISPQ_CLIENT_EXIT_CODES_H_
#define ISPQ_CLIENT_EXIT_CODES_H_

#include "absl/status/status.h"

namespace ispq::cli {

inline constexpr int kExitOk = 0;
inline constexpr int kExitUsage = 2;          // bad command line
inline constexpr int kExitInvalidInput = 3;   // unreadable file or a mesh that fails validation
inline constexpr int kExitInvalidResult = 4;  // a quantization that is not valid
inline constexpr int kExitFailed = 5;         // anything else (solver, I/O, server errors)
// The server is unreachable, busy (queue full), shutting down, or the deadline passed: the same
// command may succeed later.
inline constexpr int kExitUnavailable = 6;

// The exit code of an error a server (or the client library) reported.
inline int ExitCodeFor(const absl::Status& status) {
  switch (status.code()) {
    case absl::StatusCode::kOk:
      return kExitOk;
    case absl::StatusCode::kInvalidArgument:
      return kExitInvalidInput;
    case absl::StatusCode::kUnavailable:
    case absl::StatusCode::kResourceExhausted:
    case absl::StatusCode::kDeadlineExceeded:
      return kExitUnavailable;
    default:
      return kExitFailed;
  }
}

}  // namespace ispq::cli

#endif  // ISPQ_CLIENT_EXIT_CODES_H_
