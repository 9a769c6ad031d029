// SPDX-License-Identifier: Apache-2.0
// OPTIMALINTEGERSTEP: the best multiplicity of a sheet on a convex parabola.
#include "core/isp/integer_step.h"

#include "gtest/gtest.h"

namespace ispq {
namespace {

// f(t) = a t^2 + b t has its vertex at -b / (2a).
TEST(IntegerStepTest, RoundsTheVertex) {
  EXPECT_EQ(OptimalIntegerStep(1, -6, 1, 100), 3);     // vertex 3
  EXPECT_EQ(OptimalIntegerStep(2, -9.6, 1, 100), 2);   // vertex 2.4
  EXPECT_EQ(OptimalIntegerStep(2, -10.4, 1, 100), 3);  // vertex 2.6
}

TEST(IntegerStepTest, ClampsToTheFeasibleRange) {
  EXPECT_EQ(OptimalIntegerStep(1, 4, 1, 100), 1);  // vertex -2: at least one copy
  EXPECT_EQ(OptimalIntegerStep(1, -20, 1, 4), 4);  // vertex 10, rows allow 4
  EXPECT_EQ(OptimalIntegerStep(1, -20, 3, 3), 3);
}

TEST(IntegerStepTest, HugeVertexDoesNotOverflow) {
  EXPECT_EQ(OptimalIntegerStep(1e-300, -1, 1, int64_t{1} << 40), int64_t{1} << 40);
}

TEST(IntegerStepTest, BestIntegerIsNoWorseThanItsNeighbours) {
  for (double b = -30; b <= 5; b += 0.7) {
    const int64_t t = OptimalIntegerStep(1.3, b, 1, 50);
    auto f = [&](int64_t x) { return 1.3 * x * x + b * x; };
    if (t > 1) {
      EXPECT_LE(f(t), f(t - 1) + 1e-9) << b;
    }
    if (t < 50) {
      EXPECT_LE(f(t), f(t + 1) + 1e-9) << b;
    }
  }
}

}  // namespace
}  // namespace ispq
