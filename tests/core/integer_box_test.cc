// SPDX-License-Identifier: Apache-2.0
#include "core/integer_box.h"

#include <optional>

#include "core/direction.h"
#include "core/rotation.h"
#include "gtest/gtest.h"

namespace ispq {
namespace {

void ExpectBoxEq(const IntBox& actual, const IntBox& expected) {
  EXPECT_EQ(actual.lo, expected.lo);
  EXPECT_EQ(actual.hi, expected.hi);
}

TEST(IntegerBoxTest, VectorArithmetic) {
  EXPECT_EQ(Add({1, -2, 3}, {10, 20, -30}), (IntVec3{11, 18, -27}));
  EXPECT_EQ(Subtract({1, -2, 3}, {10, 20, -30}), (IntVec3{-9, -22, 33}));
  EXPECT_EQ(AddAlong({1, 2, 3}, Dir::kPosV, 5), (IntVec3{1, 7, 3}));
  EXPECT_EQ(AddAlong({1, 2, 3}, Dir::kNegW, 5), (IntVec3{1, 2, -2}));
  EXPECT_EQ(AddAlong({1, 2, 3}, Dir::kNegU, -4), (IntVec3{5, 2, 3}));
}

TEST(IntegerBoxTest, SpannedBoxSortsEachAxis) {
  ExpectBoxEq(SpannedBox({5, -1, 2}, {1, 3, 2}), {{1, -1, 2}, {5, 3, 2}});
  const IntBox point = PointBox({4, 5, 6});
  EXPECT_EQ(point.lo, point.hi);
  EXPECT_FALSE(IsInverted(point));
}

TEST(IntegerBoxTest, ABoxInvertedOnAnyAxisIsInverted) {
  EXPECT_FALSE(IsInverted({{0, 0, 0}, {1, 1, 1}}));
  EXPECT_TRUE(IsInverted({{0, 0, 0}, {-1, 1, 1}}));
  EXPECT_TRUE(IsInverted({{0, 0, 0}, {1, -1, 1}}));
  EXPECT_TRUE(IsInverted({{0, 0, 0}, {1, 1, -1}}));
}

// Overlap is closed: boxes that share only a face, an edge or a corner still overlap.
TEST(IntegerBoxTest, OverlapIsClosedOnEveryAxis) {
  const IntBox unit = {{0, 0, 0}, {1, 1, 1}};
  EXPECT_TRUE(Overlap(unit, {{1, 0, 0}, {2, 1, 1}}));     // shared face
  EXPECT_TRUE(Overlap(unit, {{1, 1, 1}, {2, 2, 2}}));     // shared corner
  EXPECT_TRUE(Overlap(unit, {{-5, -5, -5}, {5, 5, 5}}));  // containment
  EXPECT_FALSE(Overlap(unit, {{2, 0, 0}, {3, 1, 1}}));
  EXPECT_FALSE(Overlap(unit, {{0, -3, 0}, {1, -1, 1}}));
  EXPECT_FALSE(Overlap(unit, {{0, 0, 2}, {1, 1, 3}}));
  EXPECT_FALSE(Overlap({{0, 0, 2}, {1, 1, 3}}, unit));
}

// An inverted box (a collapsed start entity) touches nothing, even a box it would overlap.
TEST(IntegerBoxTest, AnInvertedBoxTouchesNothing) {
  const IntBox unit = {{0, 0, 0}, {1, 1, 1}};
  const IntBox inverted = {{0, 0, 1}, {1, 1, 0}};
  EXPECT_TRUE(Overlap(unit, inverted));  // Overlap alone does not look at inversion
  EXPECT_FALSE(Touches(unit, inverted));
  EXPECT_FALSE(Touches(inverted, unit));
  EXPECT_TRUE(Touches(unit, {{1, 1, 1}, {1, 1, 1}}));
  EXPECT_FALSE(Touches(unit, {{2, 2, 2}, {3, 3, 3}}));
}

// RotateBox agrees with rotating both corners and sorting, for all 24 rotations.
TEST(IntegerBoxTest, RotateBoxIsTheSortedImageOfItsCorners) {
  const IntBox box = {{-1, 2, 3}, {4, 7, 5}};
  for (int i = 0; i < Rotation::kCount; ++i) {
    const Rotation r = Rotation::FromIndex(i);
    const IntBox rotated = RotateBox(r, box);
    ExpectBoxEq(rotated, SpannedBox(r.Apply(box.lo), r.Apply(box.hi)));
    EXPECT_FALSE(IsInverted(rotated)) << i;
  }
  const std::optional<Rotation> quarter_turn = Rotation::FromSignedPermutation({-2, 1, 3});
  ASSERT_TRUE(quarter_turn.has_value());
  // (R x) = (-x1, x0, x2): u spans -7..-2, v spans -1..4, w unchanged.
  ExpectBoxEq(RotateBox(*quarter_turn, box), {{-7, -1, 3}, {-2, 4, 5}});
}

}  // namespace
}  // namespace ispq
