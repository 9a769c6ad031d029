// SPDX-License-Identifier: Apache-2.0
#include "core/zeroed_array.h"

#include <cstdint>

#include "gtest/gtest.h"

namespace ispq {
namespace {

struct Pair {
  int32_t first;
  int64_t second;
};

TEST(ZeroedArrayTest, EveryValueStartsAtZeroAndKeepsWhatIsWritten) {
  constexpr size_t kSize = 1 << 20;  // several pages, most never written below
  ZeroedArray<Pair> pairs = MakeZeroedArray<Pair>(kSize);
  ASSERT_NE(pairs, nullptr);
  for (size_t i = 0; i < kSize; i += 4099) {
    EXPECT_EQ(pairs[i].first, 0);
    EXPECT_EQ(pairs[i].second, 0);
  }
  pairs[kSize - 1] = {7, -8};
  EXPECT_EQ(pairs[kSize - 1].first, 7);
  EXPECT_EQ(pairs[kSize - 1].second, -8);
  EXPECT_EQ(pairs[kSize - 2].second, 0);
}

// calloc(0, ...) may return null, which is no allocation failure.
TEST(ZeroedArrayTest, AnEmptyArrayIsNoAllocationFailure) {
  EXPECT_NO_THROW(MakeZeroedArray<int32_t>(0));
}

}  // namespace
}  // namespace ispq
