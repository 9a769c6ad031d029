// SPDX-License-Identifier: Apache-2.0
// The 3-tier unfavorability weights of eq. (4).
#include "core/isp/sheet_weights.h"

#include <vector>

#include "gtest/gtest.h"

namespace ispq {
namespace {

constexpr double kArcs = 100;

TEST(SheetWeightsTest, TiersFollowEquationFour) {
  EXPECT_DOUBLE_EQ(SheetWeight(3.0, kArcs), 1.0 / 4);  // toward the target
  EXPECT_DOUBLE_EQ(SheetWeight(1.0, kArcs), 1.0 / 2);
  EXPECT_DOUBLE_EQ(SheetWeight(0.5, kArcs), kArcs / 1.5);  // across the target
  EXPECT_DOUBLE_EQ(SheetWeight(0.0, kArcs), kArcs);
  EXPECT_DOUBLE_EQ(SheetWeight(-1.0, kArcs), kArcs * kArcs * 2);  // away from it
}

TEST(SheetWeightsTest, EachTierOutweighsAllCheaperOnesTogether) {
  // Tier 1 weights are at most 1/2; |A| - 1 of them stay below any tier 2 weight.
  const double tier2_min = SheetWeight(0.999999, kArcs);
  EXPECT_GT(tier2_min, (kArcs - 1) * SheetWeight(1.0, kArcs));
  // Tier 3 weights exceed |A| - 1 tier 2 weights.
  EXPECT_GT(SheetWeight(-1e-9, kArcs), (kArcs - 1) * SheetWeight(0.0, kArcs));
}

TEST(SheetWeightsTest, BundlesPayForEveryArc) {
  const std::vector<double> targets = {2.5, 0.4};  // value 1: one arc wants more, one less
  const BundleWeights w = BundleSheetWeights(targets, 1.0, kArcs);
  EXPECT_DOUBLE_EQ(w.inflate, SheetWeight(1.5, kArcs) + SheetWeight(-0.6, kArcs));
  EXPECT_DOUBLE_EQ(w.deflate, SheetWeight(-1.5, kArcs) + SheetWeight(0.6, kArcs));
}

TEST(SheetWeightsTest, MarginalWeightsAreTheObjectiveChangeFloored) {
  const std::vector<double> targets = {0.2, 3.0};
  const BundleWeights w = BundleMarginalWeights(targets, 0.0, 1e-3);
  // Inflating 0 -> 1: (1 - 0.2)^2 - 0.2^2 = 0.6, and (1 - 3)^2 - 9 = -5, floored.
  EXPECT_DOUBLE_EQ(w.inflate, 0.6 + 1e-3);
  // Deflating 0 -> -1: (-1.2)^2 - 0.04 = 1.4, (-4)^2 - 9 = 7.
  EXPECT_DOUBLE_EQ(w.deflate, 1.4 + 7);
}

// CLP aborts on objective coefficients beyond 1e25 (issue 7): bundle weights are capped, and the
// cap keeps the tier order of everything below it.
TEST(SheetWeightsTest, BundleWeightsStayWithinWhatTheLpAccepts) {
  const double huge_mesh = 1e9;  // arcs
  const std::vector<double> far = {1e12, 1e12, 1e12};
  const BundleWeights away = BundleSheetWeights(far, -1e12, huge_mesh);
  EXPECT_LE(away.deflate, kMaxSheetWeight);
  EXPECT_LE(away.inflate, kMaxSheetWeight);
  const BundleWeights marginal = BundleMarginalWeights(far, 1e30, 1e-3);
  EXPECT_LE(marginal.inflate, kMaxSheetWeight);
  EXPECT_LE(marginal.deflate, kMaxSheetWeight);
  EXPECT_LT(kMaxSheetWeight, 1e25);
  // Below the cap nothing changes: a tier-3 weight of a large accepted mesh is still exact.
  const std::vector<double> one = {10.0};
  EXPECT_DOUBLE_EQ(BundleSheetWeights(one, 12.0, 5e5).inflate, SheetWeight(-2.0, 5e5));
}

}  // namespace
}  // namespace ispq
