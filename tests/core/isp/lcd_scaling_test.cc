// SPDX-License-Identifier: Apache-2.0
// Turning rational LP vertices into integer sheets (paper section 4.3.1).
#include "core/isp/lcd_scaling.h"

#include <vector>

#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace ispq {
namespace {

using ::testing::ElementsAre;
using ::testing::Optional;

TEST(LcdScalingTest, IntegersNeedNoScaling) {
  EXPECT_THAT(LeastCommonDenominator(std::vector<double>{1, -2, 7}), Optional(1));
  EXPECT_THAT(LeastCommonDenominator(std::vector<double>{}), Optional(1));
}

TEST(LcdScalingTest, HalvesFromTheUTurnGiveTwo) {
  EXPECT_THAT(LeastCommonDenominator(std::vector<double>{1, 0.5, 0.5, -1.5}), Optional(2));
}

TEST(LcdScalingTest, DenominatorsCombineByLeastCommonMultiple) {
  EXPECT_THAT(LeastCommonDenominator(std::vector<double>{0.5, 1.0 / 3}), Optional(6));
  EXPECT_THAT(LeastCommonDenominator(std::vector<double>{0.25, 0.5, 0.125}), Optional(8));
}

TEST(LcdScalingTest, SimplexNoiseIsTolerated) {
  EXPECT_THAT(LeastCommonDenominator(std::vector<double>{1 + 1e-9, 0.5 - 1e-9}), Optional(2));
}

TEST(LcdScalingTest, RejectsNonFractionsAndHugeDenominators) {
  EXPECT_EQ(LeastCommonDenominator(std::vector<double>{0.123456789}), std::nullopt);
  // 1/61 * 1/59 needs 3599 > max_lcd.
  EXPECT_EQ(LeastCommonDenominator(std::vector<double>{1.0 / 61, 1.0 / 59}), std::nullopt);
  EXPECT_EQ(LeastCommonDenominator(std::vector<double>{0.5}, 64, /*max_lcd=*/1), std::nullopt);
}

TEST(LcdScalingTest, ScalesAndRounds) {
  EXPECT_THAT(ScaleToIntegers(std::vector<double>{0.5, -1.5, 1 + 1e-9}, 2), ElementsAre(1, -3, 2));
}

}  // namespace
}  // namespace ispq
