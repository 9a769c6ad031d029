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
  EXPECT_THAT(lists.all_values(), ElementsAre(3, 1, 7));
}

// Lists appended filled and written later, out of order, as the separation search's side slots
// are written block by block.
TEST(FlatListsTest, FilledListsAreWrittenInPlaceInAnyOrder) {
  FlatLists<int> lists;
  lists.AppendFilled(2, -1);
  lists.AppendFilled(0, -1);
  lists.AppendFilled(3, -1);
  lists.MutableList(2)[1] = 5;
  lists.MutableList(0)[0] = 4;
  ASSERT_EQ(lists.size(), 3);
  EXPECT_THAT(lists[0], ElementsAre(4, -1));
  EXPECT_THAT(lists[1], IsEmpty());
  EXPECT_THAT(lists[2], ElementsAre(-1, 5, -1));
}

}  // namespace
}  // namespace ispq
