// SPDX-License-Identifier: Apache-2.0
// The inequality-row store of the sheet LPs: deduplication, values kept up to date as bundles
// move, and the count of violated active rows.
#include "core/isp/inequality_rows.h"

#include <vector>

#include "gtest/gtest.h"

namespace ispq {
namespace {

TEST(InequalityRowsTest, FindsIdenticalRowsOnly) {
  InequalityRows rows(3);
  const std::vector<int64_t> x = {0, 0, 0};
  const std::vector<LinearTerm> a = {{0, 1}, {2, -1}};
  const std::vector<LinearTerm> b = {{0, 1}, {2, 1}};
  const int32_t ra = rows.Add(a, 1, RowOrigin::kStructural, true, x);
  EXPECT_EQ(rows.Find(a, 1), ra);
  EXPECT_EQ(rows.Find(a, 0), kNoId);
  EXPECT_EQ(rows.Find(b, 1), kNoId);
  const int32_t rb = rows.Add(b, 1, RowOrigin::kFailsafe, false, x);
  EXPECT_EQ(rows.Find(b, 1), rb);
  EXPECT_EQ(rows.origin(rb), RowOrigin::kFailsafe);
}

TEST(InequalityRowsTest, ValuesFollowBundleMoves) {
  InequalityRows rows(3);
  const std::vector<int64_t> x = {2, 5, 1};
  const std::vector<LinearTerm> terms = {{0, 1}, {1, 2}, {2, -1}};
  const int32_t r = rows.Add(terms, 1, RowOrigin::kStructural, true, x);
  EXPECT_EQ(rows.value(r), 2 + 10 - 1);
  EXPECT_EQ(rows.slack(r), 10);
  rows.OnBundleMoved(1, -3);
  EXPECT_EQ(rows.value(r), 5);
  rows.OnBundleMoved(2, 4);
  EXPECT_EQ(rows.value(r), 1);
  EXPECT_FALSE(rows.violated(r));
  ASSERT_EQ(rows.rows_of_bundle(1).size(), 1u);
  EXPECT_EQ(rows.rows_of_bundle(1)[0].coef, 2);
}

TEST(InequalityRowsTest, CountsViolatedActiveRows) {
  InequalityRows rows(2);
  const std::vector<int64_t> x = {0, 0};
  const std::vector<LinearTerm> first = {{0, 1}};
  const std::vector<LinearTerm> second = {{0, 1}, {1, 1}};
  const int32_t r0 = rows.Add(first, 1, RowOrigin::kSimple, true, x);
  const int32_t r1 = rows.Add(second, 1, RowOrigin::kFailsafe, false, x);
  EXPECT_EQ(rows.num_violated_active(), 1);  // r1 is inactive
  rows.SetActive(r1, true);
  EXPECT_EQ(rows.num_violated_active(), 2);
  rows.OnBundleMoved(1, 1);  // fixes r1 only
  EXPECT_EQ(rows.num_violated_active(), 1);
  rows.OnBundleMoved(0, 1);
  EXPECT_EQ(rows.num_violated_active(), 0);
  rows.OnBundleMoved(0, -1);
  rows.SetActive(r0, false);
  EXPECT_EQ(rows.num_violated_active(), 0);
  EXPECT_TRUE(rows.violated(r0));
}

}  // namespace
}  // namespace ispq
