// SPDX-License-Identifier: Apache-2.0
#include "core/on_demand_lists.h"

#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace ispq {
namespace {

using ::testing::ElementsAre;
using ::testing::IsEmpty;

TEST(OnDemandListsTest, ListsAreBuiltInAnyOrderAndKeepTheirValues) {
  OnDemandLists<int> lists(4, 8);
  ASSERT_EQ(lists.size(), 4);
  for (int i = 0; i < 4; ++i) EXPECT_FALSE(lists.built(i));
  lists.Open(2);
  lists.Push(5);
  lists.Push(6);
  lists.Open(0);
  lists.Open(3);
  lists.Push(7);
  EXPECT_TRUE(lists.built(0));
  EXPECT_FALSE(lists.built(1));
  EXPECT_TRUE(lists.built(2));
  EXPECT_TRUE(lists.built(3));
  EXPECT_THAT(lists[2], ElementsAre(5, 6));
  EXPECT_THAT(lists[0], IsEmpty());
  EXPECT_THAT(lists[3], ElementsAre(7));
  EXPECT_EQ(lists.num_values(), 3u);
}

// Values keep their index when later lists are built, beyond the reserved room too.
TEST(OnDemandListsTest, IndicesStayValidAsListsAreAdded) {
  OnDemandLists<int> lists(100, 4);
  lists.Open(7);
  lists.Push(70);
  lists.Push(71);
  const int32_t first = lists.first_index(7);
  for (int i = 0; i < 100; ++i) {
    if (i == 7) continue;
    lists.Open(i);
    lists.Push(i);
  }
  EXPECT_EQ(lists.value(first), 70);
  EXPECT_EQ(lists.value(first + 1), 71);
  EXPECT_THAT(lists[7], ElementsAre(70, 71));
  EXPECT_THAT(lists[99], ElementsAre(99));
  EXPECT_EQ(lists.value(lists.first_index(42)), 42);
}

}  // namespace
}  // namespace ispq
