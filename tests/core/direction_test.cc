// SPDX-License-Identifier: Apache-2.0
#include "core/direction.h"

#include "gtest/gtest.h"
#include "ispq/v1/tmesh.pb.h"

namespace ispq {
namespace {

TEST(DirectionTest, EncodingHelpers) {
  EXPECT_EQ(Opposite(Dir::kPosU), Dir::kNegU);
  EXPECT_EQ(Opposite(Dir::kNegW), Dir::kPosW);
  EXPECT_EQ(AxisOf(Dir::kNegW), 2);
  EXPECT_TRUE(IsNegative(Dir::kNegV));
  EXPECT_EQ(MakeDir(1, true), Dir::kNegV);
  EXPECT_EQ(AxisBits(1), DirBit(Dir::kPosV) | DirBit(Dir::kNegV));
}

TEST(DirectionTest, DecodesTheProtoEnumsUpstreamBits) {
  EXPECT_EQ(DirFromUpstreamBits(v1::NEG_V), Dir::kNegV);
  EXPECT_EQ(DirFromUpstreamBits(v1::POS_W), Dir::kPosW);
  EXPECT_FALSE(DirFromUpstreamBits(v1::NONE).has_value());
  EXPECT_FALSE(DirFromUpstreamBits(v1::POS_U_POS_V).has_value());
  EXPECT_EQ(CornerFromUpstreamBits(v1::NEG_U_NEG_V_NEG_W), kMinCorner);
  EXPECT_EQ(CornerFromUpstreamBits(v1::POS_U_POS_V_POS_W), kMaxCorner);
  EXPECT_EQ(CornerFromUpstreamBits(v1::POS_U_NEG_V_NEG_W), 1);
  EXPECT_FALSE(CornerFromUpstreamBits(v1::POS_U_POS_V).has_value());
  // NEG_V_NEG_W runs along U at the negative v and w sides.
  EXPECT_EQ(EdgeFromUpstreamBits(v1::NEG_V_NEG_W), EdgeCode(0, false, false));
  EXPECT_EQ(EdgeFromUpstreamBits(v1::POS_U_NEG_W), EdgeCode(1, true, false));
  EXPECT_EQ(EdgeFromUpstreamBits(v1::POS_U_POS_V), EdgeCode(2, true, true));
  EXPECT_FALSE(EdgeFromUpstreamBits(v1::POS_U).has_value());
  EXPECT_FALSE(EdgeFromUpstreamBits(v1::POS_U_POS_V_POS_W).has_value());
}

// Messages about block edges name them as the file does, without the proto enum at hand.
TEST(DirectionTest, EdgeNamesAreTheProtoEnumsNames) {
  int edges = 0;
  for (int bits = 0; bits < 64; ++bits) {
    const std::optional<int> code = EdgeFromUpstreamBits(bits);
    if (!code) continue;
    ++edges;
    EXPECT_EQ(EdgeName(*code), v1::UVWDir_Name(static_cast<v1::UVWDir>(bits))) << bits;
  }
  EXPECT_EQ(edges, kNumEdges);
}

}  // namespace
}  // namespace ispq
