// SPDX-License-Identifier: Apache-2.0
#include "core/bundle_row_pair.h"

#include "core/arc_bundles.h"
#include "core/consistency_matrix.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "tests/support/test_data.h"

namespace ispq {
namespace {

using ::testing::ElementsAre;

// The cube's 12 arcs form 3 bundles of 4 parallel arcs.
class BundleRowPairTest : public ::testing::Test {
 protected:
  BundleRowPairTest()
      : cube_(testing::LoadTMeshOrDie(testing::RealTMeshPath("hex-me/s01c_cube.tmesh.json"))),
        consistency_(cube_),
        bundles_(cube_, consistency_) {}

  ArcId Arc(BundleId b, int k) const { return bundles_.arcs(b)[k]; }

  TMesh cube_;
  ConsistencyMatrix consistency_;
  ArcBundles bundles_;
};

TEST_F(BundleRowPairTest, KeepsADefaultRowThatSurvivesBundling) {
  const SeparationRow default_row{{{Arc(0, 0), 1}, {Arc(1, 0), -1}}, 1};
  const SeparationRow failsafe_row{{{Arc(0, 0), 1}}, 1};
  const BundleRowPair pair = ToBundleRowPair(bundles_, default_row, failsafe_row);
  EXPECT_THAT(pair.default_terms, ElementsAre(LinearTerm{0, 1}, LinearTerm{1, -1}));
  EXPECT_EQ(pair.default_rhs, 1);
  EXPECT_THAT(pair.failsafe_terms, ElementsAre(LinearTerm{0, 1}));
  EXPECT_EQ(pair.failsafe_rhs, 1);
}

TEST_F(BundleRowPairTest, TheTwinStandsInForADefaultRowThatBundlingEmpties) {
  // q_a - q_b >= 1 over two arcs of one bundle reads 0 >= 1: it can never hold.
  const SeparationRow default_row{{{Arc(2, 0), 1}, {Arc(2, 3), -1}}, 1};
  const SeparationRow failsafe_row{{{Arc(2, 0), 1}, {Arc(1, 2), 1}}, 1};
  const BundleRowPair pair = ToBundleRowPair(bundles_, default_row, failsafe_row);
  EXPECT_THAT(pair.default_terms, ElementsAre(LinearTerm{1, 1}, LinearTerm{2, 1}));
  EXPECT_EQ(pair.default_rhs, 1);
  EXPECT_EQ(pair.failsafe_terms, pair.default_terms);
}

TEST_F(BundleRowPairTest, RepeatedBundlesAddUp) {
  const SeparationRow row{{{Arc(0, 0), 1}, {Arc(0, 1), 1}, {Arc(2, 1), 1}}, 2};
  const BundleRowPair pair = ToBundleRowPair(bundles_, row, row);
  EXPECT_THAT(pair.default_terms, ElementsAre(LinearTerm{0, 2}, LinearTerm{2, 1}));
  EXPECT_EQ(pair.default_rhs, 2);
}

}  // namespace
}  // namespace ispq
