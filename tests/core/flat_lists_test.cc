// SPDX-License-Identifier: Apache-2.0
#include "core/flat_lists.h"

#include <vector>

#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace ispq {
namespace {

using ::testing::ElementsAre;
using ::testing::IsEmpty;

TEST(FlatListsTest, ListsKeepTheirValuesInOrder) {
  FlatLists<int> lists;
  lists.Append(std::vector<int>{3, 1});
  lists.OpenList();
  lists.PushToLast(7);
  lists.Append(std::vector<int>{});
  ASSERT_EQ(lists.size(), 3);
  EXPECT_THAT(lists[0], ElementsAre(3, 1));
  EXPECT_THAT(lists[1], ElementsAre(7));
  EXPECT_THAT(lists[2], IsEmpty());
}

}  // namespace
}  // namespace ispq
