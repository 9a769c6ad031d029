#include "core/direction.h"

#include "gtest/gtest.h"

namespace ispq {
namespace {

TEST(DirectionTest, OppositeAndAxis) {
  EXPECT_EQ(Opposite(Dir::kPosU), Dir::kNegU);
  EXPECT_EQ(AxisOf(Dir::kNegW), 2);
}

}  // namespace
}  // namespace ispq
