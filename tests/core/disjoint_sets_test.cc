// SPDX-License-Identifier: Apache-2.0
#include "core/disjoint_sets.h"

#include <cstdint>

#include "gtest/gtest.h"

namespace ispq {
namespace {

TEST(DisjointSetsTest, EveryIdStartsAlone) {
  DisjointSets sets(4);
  for (int32_t i = 0; i < 4; ++i) EXPECT_EQ(sets.Find(i), i);
}

// Bundles and subproblems are numbered by the representative, so it must be the smallest member
// whichever order the joins come in.
TEST(DisjointSetsTest, TheRepresentativeIsTheSmallestMemberWhateverTheJoinOrder) {
  DisjointSets sets(8);
  sets.Join(7, 5);
  sets.Join(6, 7);
  EXPECT_EQ(sets.Find(6), 5);
  sets.Join(6, 3);  // joins through a non-representative member
  for (int32_t i : {3, 5, 6, 7}) EXPECT_EQ(sets.Find(i), 3) << i;
  sets.Join(1, 2);
  sets.Join(7, 2);  // merges two groups of several members each
  for (int32_t i : {1, 2, 3, 5, 6, 7}) EXPECT_EQ(sets.Find(i), 1) << i;
  EXPECT_EQ(sets.Find(0), 0);
  EXPECT_EQ(sets.Find(4), 4);
}

TEST(DisjointSetsTest, JoiningWithinOneSetChangesNothing) {
  DisjointSets sets(3);
  sets.Join(2, 1);
  sets.Join(1, 2);
  sets.Join(2, 2);
  EXPECT_EQ(sets.Find(2), 1);
  EXPECT_EQ(sets.Find(1), 1);
  EXPECT_EQ(sets.Find(0), 0);
}

// A long chain exercises path halving: every member still finds the same root.
TEST(DisjointSetsTest, ALongChainFindsItsRootFromEveryMember) {
  constexpr int kSize = 1000;
  DisjointSets sets(kSize);
  for (int32_t i = kSize - 1; i > 0; --i) sets.Join(i, i - 1);
  for (int32_t i = kSize - 1; i >= 0; --i) EXPECT_EQ(sets.Find(i), 0) << i;
}

}  // namespace
}  // namespace ispq
