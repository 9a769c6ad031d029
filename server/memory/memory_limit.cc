// SPDX-License-Identifier: Apache-2.0
#include "server/memory/memory_limit.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "absl/status/status.h"
#include "absl/strings/ascii.h"
#include "absl/strings/match.h"
#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_split.h"
#include "absl/strings/strip.h"

namespace ispq::server {
namespace {

constexpr char kCgroupRoot[] = "/sys/fs/cgroup";
// cgroup v1 reports "no limit" as a huge page-rounded number.
constexpr int64_t kUnlimited = int64_t{1} << 60;

std::optional<int64_t> ReadLimitFile(const std::string& path) {
  std::ifstream in(path);
  std::string text;
  if (!(in >> text)) return std::nullopt;
  int64_t value = 0;
  if (text == "max" || !absl::SimpleAtoi(text, &value) || value <= 0 || value >= kUnlimited) {
    return std::nullopt;
  }
  return value;
}

// The cgroup directories of this process, innermost first, for the v2 hierarchy and the v1
// memory controller ("0::/a/b" and "4:memory:/a/b" in /proc/self/cgroup).
std::vector<std::string> LimitFiles() {
  std::vector<std::string> files;
  std::ifstream in("/proc/self/cgroup");
  std::string line;
  while (std::getline(in, line)) {
    const std::vector<std::string> parts = absl::StrSplit(line, absl::MaxSplits(':', 2));
    if (parts.size() != 3) continue;
    std::string directory;
    std::string file;
    if (parts[0] == "0" && parts[1].empty()) {
      directory = absl::StrCat(kCgroupRoot, parts[2]);
      file = "memory.max";
    } else if (absl::StrContains(parts[1], "memory")) {
      directory = absl::StrCat(kCgroupRoot, "/memory", parts[2]);
      file = "memory.limit_in_bytes";
    } else {
      continue;
    }
    // A limit on an ancestor holds too; inside a container the hierarchy may start anywhere.
    while (true) {
      files.push_back(absl::StrCat(directory, "/", file));
      const size_t slash = directory.find_last_of('/');
      if (slash == std::string::npos || directory.size() <= sizeof(kCgroupRoot)) break;
      directory.resize(slash);
    }
  }
  files.push_back(absl::StrCat(kCgroupRoot, "/memory.max"));
  files.push_back(absl::StrCat(kCgroupRoot, "/memory/memory.limit_in_bytes"));
  return files;
}

int64_t PhysicalMemory() {
  const long pages = sysconf(_SC_PHYS_PAGES);
  const long page_size = sysconf(_SC_PAGESIZE);
  if (pages <= 0 || page_size <= 0) return int64_t{4} << 30;  // unknown: assume a small machine
  return static_cast<int64_t>(pages) * page_size;
}

}  // namespace

absl::StatusOr<int64_t> ParseByteSize(absl::string_view text) {
  static constexpr std::pair<absl::string_view, double> kUnits[] = {{"KiB", 1024.0},
                                                                    {"MiB", 1024.0 * 1024},
                                                                    {"GiB", 1024.0 * 1024 * 1024},
                                                                    {"KB", 1e3},
                                                                    {"MB", 1e6},
                                                                    {"GB", 1e9},
                                                                    {"K", 1024.0},
                                                                    {"M", 1024.0 * 1024},
                                                                    {"G", 1024.0 * 1024 * 1024},
                                                                    {"B", 1.0}};
  absl::string_view number = absl::StripAsciiWhitespace(text);
  double unit = 1.0;
  for (const auto& [suffix, factor] : kUnits) {
    if (absl::ConsumeSuffix(&number, suffix)) {
      unit = factor;
      break;
    }
  }
  double value = 0;
  if (!absl::SimpleAtod(absl::StripAsciiWhitespace(number), &value) || !std::isfinite(value) ||
      value * unit < 1 || value * unit > 9.0e18) {
    return absl::InvalidArgumentError(
        absl::StrCat("'", text, "' is not a positive byte size such as 536870912 or 512MiB"));
  }
  return static_cast<int64_t>(value * unit);
}

std::optional<int64_t> CgroupMemoryLimit() {
  std::optional<int64_t> limit;
  for (const std::string& file : LimitFiles()) {
    if (std::optional<int64_t> value = ReadLimitFile(file); value.has_value()) {
      limit = std::min(limit.value_or(*value), *value);
    }
  }
  return limit;
}

int64_t DefaultMemoryBudget() {
  const int64_t physical = PhysicalMemory();
  if (std::optional<int64_t> cgroup = CgroupMemoryLimit(); cgroup.has_value()) {
    return std::min(*cgroup, physical) / 4 * 3;
  }
  return physical / 2;
}

}  // namespace ispq::server
