// SPDX-License-Identifier: Apache-2.0
#include "core/resolution_levels.h"

#include <vector>

#include "gtest/gtest.h"

namespace ispq {
namespace {

TEST(ResolutionLevelsTest, MatchesTheFormatDefinition) {
  const std::vector<double> lengths = {4.0, 1.0, 2.0, 8.0};
  EXPECT_DOUBLE_EQ(*ScalingForPercent(lengths, 0), 0.5 / 1.0);
  EXPECT_DOUBLE_EQ(*ScalingForPercent(lengths, 25), 0.5 / 2.0);  // k = 1
  EXPECT_DOUBLE_EQ(*ScalingForPercent(lengths, 50), 0.5 / 4.0);  // k = 2
  EXPECT_DOUBLE_EQ(*ScalingForPercent(lengths, 100), 0.999 * 0.5 / 8.0);
  EXPECT_DOUBLE_EQ(*ScalingForPercent(lengths, 10), 0.5 / 1.0);  // round(0.4) = 0
  EXPECT_DOUBLE_EQ(*ScalingForPercent(lengths, 63), 0.5 / 8.0);  // round(2.52) = 3
  EXPECT_FALSE(ScalingForPercent({}, 5).has_value());
  EXPECT_FALSE(ScalingForPercent(lengths, 101).has_value());
}

}  // namespace
}  // namespace ispq
