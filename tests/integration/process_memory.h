// SPDX-License-Identifier: Apache-2.0
// The memory a process has used, from /proc/PID/status, for tests that hold the server to its
// memory budget: VmHWM is the peak resident set size since the process started.
#ifndef ISPQ_TESTS_INTEGRATION_PROCESS_MEMORY_H_
#define ISPQ_TESTS_INTEGRATION_PROCESS_MEMORY_H_

#include <sys/types.h>

#include <cstdint>

#include "absl/status/statusor.h"

namespace ispq::testing {

inline constexpr int64_t kMiB = 1 << 20;

// The peak resident set size (VmHWM) of `pid`, in bytes.
absl::StatusOr<int64_t> PeakResidentBytes(pid_t pid);

}  // namespace ispq::testing

#endif  // ISPQ_TESTS_INTEGRATION_PROCESS_MEMORY_H_
