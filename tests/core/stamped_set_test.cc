// SPDX-License-Identifier: Apache-2.0
#include "core/stamped_set.h"

#include "gtest/gtest.h"

namespace ispq {
namespace {

TEST(StampedSetTest, InsertedIdsAreContainedUntilCleared) {
  StampedSet set;
  set.Resize(5);
  for (int i = 0; i < 5; ++i) EXPECT_FALSE(set.Contains(i));
  set.Insert(1);
  set.Insert(4);
  EXPECT_TRUE(set.Contains(1));
  EXPECT_TRUE(set.Contains(4));
  EXPECT_FALSE(set.Contains(0));
  set.Clear();
  for (int i = 0; i < 5; ++i) EXPECT_FALSE(set.Contains(i)) << i;
  set.Insert(0);
  EXPECT_TRUE(set.Contains(0));
  EXPECT_FALSE(set.Contains(1));
}

TEST(StampedSetTest, ResizeEmptiesTheSet) {
  StampedSet set;
  set.Resize(3);
  set.Insert(2);
  set.Clear();
  set.Insert(1);
  set.Resize(4);
  for (int i = 0; i < 4; ++i) EXPECT_FALSE(set.Contains(i)) << i;
}

}  // namespace
}  // namespace ispq
