// SPDX-License-Identifier: Apache-2.0
#include "tests/integration/process_memory.h"

#include <fstream>
#include <string>

#include "absl/status/status.h"
#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/strip.h"

namespace ispq::testing {

absl::StatusOr<int64_t> PeakResidentBytes(pid_t pid) {
  const std::string path = absl::StrCat("/proc/", pid, "/status");
  std::ifstream status(path);
  std::string line;
  while (std::getline(status, line)) {
    absl::string_view value = line;
    if (!absl::ConsumePrefix(&value, "VmHWM:")) continue;
    value = absl::StripAsciiWhitespace(value);
    int64_t kilobytes = 0;
    if (absl::ConsumeSuffix(&value, " kB") && absl::SimpleAtoi(value, &kilobytes)) {
      return kilobytes * 1024;
    }
    return absl::InternalError(absl::StrCat("unreadable line in ", path, ": ", line));
  }
  return absl::NotFoundError(absl::StrCat("no VmHWM in ", path));
}

}  // namespace ispq::testing
