// SPDX-License-Identifier: Apache-2.0
#include "core/linear_terms.h"

#include <cstdint>
#include <map>
#include <random>
#include <vector>

#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace ispq {
namespace {

using ::testing::ElementsAre;

struct DoubleTerm {
  int32_t var;
  double coef;
  friend bool operator==(const DoubleTerm&, const DoubleTerm&) = default;
};

TEST(MergeRepeatedTermsTest, SumsRepeatsIntoTheFirstAndDropsZeros) {
  std::vector<LinearTerm> terms = {{7, 1}, {3, 1}, {7, -1}, {5, 2}, {3, 1}};
  MergeRepeatedTerms(terms);
  EXPECT_THAT(terms, ElementsAre(LinearTerm{3, 2}, LinearTerm{5, 2}));
}

TEST(MergeRepeatedTermsTest, LeavesTermsBeforeBeginAlone) {
  std::vector<DoubleTerm> terms = {{1, 1.0}, {1, 1.0}, {2, 0.5}, {2, 0.25}, {1, 3.0}};
  MergeRepeatedTerms(terms, 2);
  EXPECT_THAT(terms, ElementsAre(DoubleTerm{1, 1.0}, DoubleTerm{1, 1.0}, DoubleTerm{2, 0.75},
                                 DoubleTerm{1, 3.0}));
}

TEST(MergeRepeatedTermsTest, EmptyAndAllCancellingRowsBecomeEmpty) {
  std::vector<LinearTerm> empty;
  MergeRepeatedTerms(empty);
  EXPECT_TRUE(empty.empty());
  std::vector<LinearTerm> cancelling;
  for (int i = 0; i < 40; ++i) cancelling.push_back({i % 7, i % 2 == 0 ? 1 : -1});
  cancelling.push_back({0, 0});
  MergeRepeatedTerms(cancelling);
  for (const LinearTerm& t : cancelling) EXPECT_NE(t.coef, 0);
}

// The reference: the order of first appearance and each variable's sum in order of appearance.
std::vector<DoubleTerm> Reference(const std::vector<DoubleTerm>& terms) {
  std::vector<int32_t> order;
  std::map<int32_t, double> sum;
  for (const DoubleTerm& t : terms) {
    if (!sum.contains(t.var)) order.push_back(t.var);
    sum[t.var] += t.coef;
  }
  std::vector<DoubleTerm> merged;
  for (int32_t v : order) {
    if (sum[v] != 0) merged.push_back({v, sum[v]});
  }
  return merged;
}

// Short rows are merged by a scan, long ones by sorting: both must give the reference's row
// exactly, sums included (the LP back ends must see the same row whichever path ran).
TEST(MergeRepeatedTermsTest, ShortAndLongRowsMatchTheReference) {
  std::mt19937 random(11);
  for (int size : {1, 2, 5, 16, 17, 40, 300}) {
    for (int trial = 0; trial < 50; ++trial) {
      std::uniform_int_distribution<int32_t> var(0, size / 2 + 1);
      std::uniform_int_distribution<int> coef(-3, 3);
      std::vector<DoubleTerm> terms;
      for (int i = 0; i < size; ++i) terms.push_back({var(random), 0.1 * coef(random)});
      const std::vector<DoubleTerm> expected = Reference(terms);
      MergeRepeatedTerms(terms);
      ASSERT_EQ(terms, expected) << "size " << size << " trial " << trial;
    }
  }
}

}  // namespace
}  // namespace ispq
