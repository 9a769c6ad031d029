// SPDX-License-Identifier: Apache-2.0
#include "server/memory/memory_limit.h"

#include <unistd.h>

#include "gtest/gtest.h"

namespace ispq::server {
namespace {

TEST(MemoryLimitTest, ParsesByteSizesWithBinaryAndDecimalUnits) {
  EXPECT_EQ(*ParseByteSize("536870912"), 536870912);
  EXPECT_EQ(*ParseByteSize("512MiB"), 512LL << 20);
  EXPECT_EQ(*ParseByteSize("2GiB"), 2LL << 30);
  EXPECT_EQ(*ParseByteSize("1.5GiB"), 3LL << 29);
  EXPECT_EQ(*ParseByteSize("64KiB"), 64 << 10);
  EXPECT_EQ(*ParseByteSize("2G"), 2LL << 30);
  EXPECT_EQ(*ParseByteSize("500MB"), 500'000'000);
  EXPECT_EQ(*ParseByteSize(" 1 GB "), 1'000'000'000);
}

TEST(MemoryLimitTest, RefusesWhatIsNoPositiveSize) {
  for (const char* text : {"", "MiB", "-1GiB", "0", "lots", "1TiB", "nan", "1e30"}) {
    const absl::StatusOr<int64_t> parsed = ParseByteSize(text);
    EXPECT_EQ(parsed.status().code(), absl::StatusCode::kInvalidArgument) << "'" << text << "'";
  }
}

TEST(MemoryLimitTest, TheDefaultFitsThisMachine) {
  const int64_t physical = static_cast<int64_t>(sysconf(_SC_PHYS_PAGES)) * sysconf(_SC_PAGESIZE);
  const int64_t budget = DefaultMemoryBudget();
  EXPECT_GT(budget, 0);
  EXPECT_LE(budget, physical * 3 / 4);
  if (const std::optional<int64_t> cgroup = CgroupMemoryLimit(); cgroup.has_value()) {
    EXPECT_LE(budget, *cgroup / 4 * 3);
  } else {
    EXPECT_EQ(budget, physical / 2);
  }
}

}  // namespace
}  // namespace ispq::server
