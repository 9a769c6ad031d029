// SPDX-License-Identifier: Apache-2.0
// The subproblems of a run: one per initial component, rows routed to their LPs, merges when a
// row couples two; and the row roles on top of them (core/isp/separation_rows.h): C active from
// the start with its floors, simple rows held aside and activated all at once, structural rows
// with their failsafe twins.
#include "core/isp/subproblem_set.h"

#include <vector>

#include "core/arc_bundles.h"
#include "core/consistency_matrix.h"
#include "core/isp/bundle_quantization.h"
#include "core/isp/clp_sheet_lp.h"
#include "core/isp/separation_rows.h"
#include "core/subproblems.h"
#include "gtest/gtest.h"
#include "tests/support/grid_tmesh_builder.h"
#include "tests/support/test_data.h"

namespace ispq {
namespace {

// Two blocks side by side along u: bundles u1, u2 (each block's u edges), v and w; four initial
// subproblems, since only consistency and extent rows join bundles.
class SubproblemSetTest : public ::testing::Test {
 protected:
  SubproblemSetTest()
      : grid_(*testing::BuildGridTMesh(Spec())),
        mesh_(testing::TMeshOrDie(grid_.proto())),
        consistency_(mesh_),
        bundles_(mesh_, consistency_),
        quantization_(mesh_, bundles_, 1.0),
        initial_(mesh_, consistency_, bundles_),
        rows_(mesh_, bundles_, quantization_, /*per_arc_nonnegative=*/false),
        set_(consistency_, bundles_, initial_, quantization_, rows_.store(), rows_.Floors(),
             mesh_.num_arcs(), ClpSheetLpFactory(), /*decompose=*/true) {}

  static testing::GridTMeshSpec Spec() {
    testing::GridTMeshSpec spec;
    spec.blocks = {{{0, 0, 0}, {1, 1, 1}}, {{1, 0, 0}, {2, 1, 1}}};
    return spec;
  }
  BundleId Bundle(const testing::GridPoint& a, const testing::GridPoint& b) const {
    return bundles_.bundle_of(grid_.ArcBetween(a, b));
  }

  const testing::GridTMesh grid_;
  const TMesh mesh_;
  const ConsistencyMatrix consistency_;
  const ArcBundles bundles_;
  BundleQuantization quantization_;
  const Subproblems initial_;
  SeparationRows rows_;
  SubproblemSet set_;
};

TEST_F(SubproblemSetTest, StartsWithTheInitialSubproblemsAndTheirExtentRows) {
  EXPECT_EQ(bundles_.num_bundles(), 4);
  EXPECT_EQ(set_.count(), 4);
  // C: one extent row per bundle and block axis, deduplicated, active, each a floor x_b >= 0.
  EXPECT_EQ(rows_.store().size(), 4);
  for (int32_t r = 0; r < rows_.store().size(); ++r) EXPECT_TRUE(rows_.store().active(r));
  for (uint8_t floor : rows_.Floors()) EXPECT_EQ(floor, 1);
  // At q = 0 the extent rows hold; the links (the 12 box edges) are collapsed.
  EXPECT_TRUE(set_.WithViolatedRows().empty());
  EXPECT_GT(rows_.NumViolated(), 0);
  EXPECT_TRUE(rows_.AnyHeldSimpleRowViolated());
}

TEST_F(SubproblemSetTest, SimpleRowsAreActivatedAllAtOnceAndAttached) {
  std::vector<int32_t> attach = rows_.ActivateSimpleRows(set_);
  EXPECT_TRUE(rows_.simple_rows_active());
  EXPECT_FALSE(attach.empty());
  for (int32_t r : attach) EXPECT_FALSE(set_.MarkRowChanged(r)) << "not in an LP yet";
  set_.Attach(attach);
  for (int32_t r : attach) EXPECT_TRUE(set_.MarkRowChanged(r));
  // The violations are now counted among the active rows (each distinct row once: the four
  // v-edge links are one row over bundles), none held aside any more.
  EXPECT_GT(rows_.store().num_violated_active(), 0);
  EXPECT_EQ(rows_.NumViolated(), rows_.store().num_violated_active());
  EXPECT_FALSE(rows_.AnyHeldSimpleRowViolated());
  EXPECT_FALSE(set_.WithViolatedRows().empty());
}

TEST_F(SubproblemSetTest, ARowCouplingTwoSubproblemsMergesThem) {
  const BundleId u1 = Bundle({0, 0, 0}, {1, 0, 0});
  const BundleId u2 = Bundle({1, 0, 0}, {2, 0, 0});
  ASSERT_NE(&set_.Of(u1), &set_.Of(u2));
  SeparationViolation violation;
  violation.default_row.terms = {{grid_.ArcBetween({0, 0, 0}, {1, 0, 0}), 1},
                                 {grid_.ArcBetween({1, 0, 0}, {2, 0, 0}), -1}};
  violation.failsafe_row.terms = {{grid_.ArcBetween({0, 0, 0}, {1, 0, 0}), 1}};
  std::vector<int32_t> attach;
  EXPECT_EQ(rows_.AddViolations({&violation, 1}, {.rows = 1}, set_, &attach).activated, 1);
  // The default row is active and new; its failsafe twin is stored, inactive.
  ASSERT_EQ(attach.size(), 1u);
  EXPECT_EQ(rows_.store().size(), 6);
  set_.Attach(attach);
  EXPECT_EQ(set_.count(), 3);
  EXPECT_EQ(&set_.Of(u1), &set_.Of(u2));
  // Found again, the row is neither added nor activated twice.
  attach.clear();
  EXPECT_EQ(rows_.AddViolations({&violation, 1}, {.rows = 1}, set_, &attach).activated, 0);
  EXPECT_TRUE(attach.empty());
}

TEST_F(SubproblemSetTest, FailsafeFormsStandInForDefaultRowsAndGoBack) {
  SeparationViolation violation;
  violation.default_row.terms = {{grid_.ArcBetween({0, 0, 0}, {1, 0, 0}), 1},
                                 {grid_.ArcBetween({1, 0, 0}, {2, 0, 0}), -1}};
  violation.failsafe_row.terms = {{grid_.ArcBetween({0, 0, 0}, {1, 0, 0}), 1}};
  std::vector<int32_t> attach;
  rows_.AddViolations({&violation, 1}, {.rows = 1}, set_, &attach);
  set_.Attach(attach);
  const int32_t default_row = attach[0];
  const int32_t failsafe_row = rows_.store().size() - 1;
  const std::vector<int32_t> violated = set_.WithViolatedRows();
  ASSERT_EQ(violated.size(), 1u);

  const std::vector<SeparationRows::Swap> swaps = rows_.UseFailsafeForms(violated[0], set_);
  ASSERT_EQ(swaps.size(), 1u);
  EXPECT_EQ(swaps[0], (SeparationRows::Swap{default_row, failsafe_row}));
  EXPECT_FALSE(rows_.store().active(default_row));
  EXPECT_TRUE(rows_.store().active(failsafe_row));
  EXPECT_TRUE(set_.MarkRowChanged(failsafe_row)) << "attached to the subproblem's LP";
  // Still violated at q = 0: the failsafe form keeps standing in.
  rows_.RestoreDefaultForms(swaps, set_.at(violated[0]));
  EXPECT_FALSE(rows_.store().active(default_row));
  EXPECT_TRUE(rows_.store().active(failsafe_row));
}

}  // namespace
}  // namespace ispq
