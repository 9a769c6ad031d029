// SPDX-License-Identifier: Apache-2.0
#include "core/rotation.h"

#include <set>

#include "gtest/gtest.h"

namespace ispq {
namespace {

TEST(RotationTest, TwentyFourDistinctProperRotations) {
  std::set<std::array<int, 3>> seen;
  for (int i = 0; i < Rotation::kCount; ++i)
    seen.insert(Rotation::FromIndex(i).SignedPermutation());
  EXPECT_EQ(seen.size(), 24u);
  EXPECT_TRUE(Rotation().IsIdentity());
  EXPECT_EQ(Rotation().SignedPermutation(), (std::array<int, 3>{1, 2, 3}));
}

TEST(RotationTest, RejectsImproperAndMalformedPermutations) {
  EXPECT_FALSE(Rotation::FromSignedPermutation({-1, 2, 3}).has_value());  // a reflection
  EXPECT_FALSE(Rotation::FromSignedPermutation({2, 1, 3}).has_value());   // odd permutation
  EXPECT_FALSE(Rotation::FromSignedPermutation({1, 1, 3}).has_value());
  EXPECT_FALSE(Rotation::FromSignedPermutation({0, 2, 3}).has_value());
  EXPECT_FALSE(Rotation::FromSignedPermutation({1, 2, 4}).has_value());
  EXPECT_TRUE(Rotation::FromSignedPermutation({-2, 1, 3}).has_value());
}

TEST(RotationTest, ActsAsTheFormatDefines) {
  // (R x)_i = sign(r_i) * x[|r_i| - 1]; r = (-2, 1, 3) is a quarter turn about w.
  const Rotation r = *Rotation::FromSignedPermutation({-2, 1, 3});
  EXPECT_EQ(r.Apply(std::array<int64_t, 3>{1, 0, 0}), (std::array<int64_t, 3>{0, 1, 0}));
  EXPECT_EQ(r.Apply(std::array<int64_t, 3>{0, 1, 0}), (std::array<int64_t, 3>{-1, 0, 0}));
  EXPECT_EQ(r.Apply(Dir::kPosU), Dir::kPosV);
  EXPECT_EQ(r.Apply(Dir::kPosV), Dir::kNegU);
  EXPECT_EQ(r.Apply(Dir::kNegW), Dir::kNegW);
}

TEST(RotationTest, CompositionAndInverseMatchVectorAction) {
  const std::array<int64_t, 3> x = {3, -5, 7};
  for (int i = 0; i < Rotation::kCount; ++i) {
    const Rotation a = Rotation::FromIndex(i);
    EXPECT_EQ(a.Inverse().Apply(a.Apply(x)), x);
    EXPECT_TRUE(a.Inverse().After(a).IsIdentity());
    for (int j = 0; j < Rotation::kCount; ++j) {
      const Rotation b = Rotation::FromIndex(j);
      EXPECT_EQ(b.After(a).Apply(x), b.Apply(a.Apply(x)));
      for (Dir d : kAllDirs) EXPECT_EQ(b.After(a).Apply(d), b.Apply(a.Apply(d)));
    }
  }
}

}  // namespace
}  // namespace ispq
