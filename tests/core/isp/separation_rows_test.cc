// SPDX-License-Identifier: Apache-2.0
// The row roles of one ISP run beyond what tests/core/isp/subproblem_set_test.cc shows (merging,
// attaching, one failsafe swap): the per-subproblem cap on new rows of a search round, the rows
// a result is certified against, failsafe twins shared by several default rows, found rows that
// are also simple rows, and the per-arc bounds.
#include "core/isp/separation_rows.h"

#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

#include "core/arc_bundles.h"
#include "core/consistency_matrix.h"
#include "core/isp/bundle_quantization.h"
#include "core/isp/clp_sheet_lp.h"
#include "core/isp/inequality_rows.h"
#include "core/isp/subproblem_set.h"
#include "core/separation_search.h"
#include "core/subproblems.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "tests/support/grid_tmesh_builder.h"
#include "tests/support/test_data.h"

namespace ispq {
namespace {

using ::testing::ElementsAre;
using ::testing::UnorderedElementsAre;

testing::GridTMeshSpec TwoBlocksAlongU() {
  testing::GridTMeshSpec spec;
  spec.blocks = {{{0, 0, 0}, {1, 1, 1}}, {{1, 0, 0}, {2, 1, 1}}};
  return spec;
}

// A block next to a taller one: the tall block's w edges on the far side are one bundle, those
// on the near side two (split by the low block's top), so not every bundle has an extent row.
testing::GridTMeshSpec Step() {
  testing::GridTMeshSpec spec;
  spec.blocks = {{{0, 0, 0}, {1, 1, 2}}, {{1, 0, 0}, {2, 1, 1}}};
  return spec;
}

// Everything SeparationRows works with, for one grid mesh, at q = 0.
class IspRows {
 public:
  IspRows(const testing::GridTMeshSpec& spec, bool decompose, bool per_arc_nonnegative)
      : grid_(*testing::BuildGridTMesh(spec)),
        mesh_(testing::TMeshOrDie(grid_.proto())),
        consistency_(mesh_),
        bundles_(mesh_, consistency_),
        quantization_(mesh_, bundles_, 1.0),
        initial_(mesh_, consistency_, bundles_),
        rows_(mesh_, bundles_, quantization_, per_arc_nonnegative),
        set_(consistency_, bundles_, initial_, quantization_, rows_.store(), rows_.Floors(),
             mesh_.num_arcs(), ClpSheetLpFactory(), decompose) {}

  ArcId Arc(const testing::GridPoint& a, const testing::GridPoint& b) const {
    return grid_.ArcBetween(a, b);
  }
  BundleId Bundle(const testing::GridPoint& a, const testing::GridPoint& b) const {
    return bundles_.bundle_of(Arc(a, b));
  }
  // Moves bundle b by delta, in the quantization and in the rows' values.
  void Move(BundleId b, int64_t delta) {
    std::vector<int64_t> values(quantization_.values().begin(), quantization_.values().end());
    values[b] += delta;
    quantization_.SetValues(values);
    rows_.OnBundleMoved(b, delta);
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

// A violation whose default row is `default_terms` >= 1 and failsafe row `failsafe_terms` >= 1
// (over arcs).
SeparationViolation Violation(std::vector<LinearTerm> default_terms,
                              std::vector<LinearTerm> failsafe_terms) {
  SeparationViolation v;
  v.default_row.terms = std::move(default_terms);
  v.failsafe_row.terms = std::move(failsafe_terms);
  return v;
}
SeparationViolation Violation(std::vector<LinearTerm> terms) { return Violation(terms, terms); }

// The cap is `rows`, or one row per `bundles_per_extra_row` bundles of the subproblem if that is
// more (the tuning's max(2, bundles / bundles_per_extra_new_row)).
TEST(SeparationRowsTest, NewRowCapGrowsWithTheSubproblemsBundles) {
  IspRows whole(TwoBlocksAlongU(), /*decompose=*/false, false);
  ASSERT_EQ(whole.set_.count(), 1);
  const SheetSubproblem& four = whole.set_.at(whole.set_.Ids()[0]);
  ASSERT_EQ(four.bundles().size(), 4u);
  EXPECT_EQ((NewRowCap{.rows = 2, .bundles_per_extra_row = 0}).For(four), 2);
  EXPECT_EQ((NewRowCap{.rows = 2, .bundles_per_extra_row = 1}).For(four), 4);
  EXPECT_EQ((NewRowCap{.rows = 2, .bundles_per_extra_row = 2}).For(four), 2);
  EXPECT_EQ((NewRowCap{.rows = 1, .bundles_per_extra_row = 2}).For(four), 2);
  EXPECT_EQ((NewRowCap{.rows = 1, .bundles_per_extra_row = 3}).For(four), 1);
  EXPECT_EQ((NewRowCap{.rows = 1, .bundles_per_extra_row = 5}).For(four), 1);
  EXPECT_EQ((NewRowCap{.rows = 3, .bundles_per_extra_row = -1}).For(four), 3);
  IspRows parts(TwoBlocksAlongU(), /*decompose=*/true, false);
  ASSERT_EQ(parts.set_.count(), 4);
  const SheetSubproblem& one = parts.set_.at(0);
  ASSERT_EQ(one.bundles().size(), 1u);
  EXPECT_EQ((NewRowCap{.rows = 2, .bundles_per_extra_row = 1}).For(one), 2);
}

// Rows of a round go to their subproblem (by the failsafe row's first bundle) until its cap;
// later ones there are dropped while other subproblems still take theirs.
TEST(SeparationRowsTest, TheCapHoldsPerSubproblemAndDropsTheRest) {
  IspRows run(TwoBlocksAlongU(), /*decompose=*/true, false);
  const ArcId u1a = run.Arc({0, 0, 0}, {1, 0, 0}), u1b = run.Arc({0, 1, 0}, {1, 1, 0}),
              u1c = run.Arc({0, 0, 1}, {1, 0, 1});
  const ArcId v = run.Arc({0, 0, 0}, {0, 1, 0});
  // Three distinct rows over bundle u1 (coefficients 1, 2, 3 once bundled) and one over v.
  const std::vector<SeparationViolation> round = {
      Violation({{u1a, 1}}), Violation({{u1a, 1}, {u1b, 1}}),
      Violation({{u1a, 1}, {u1b, 1}, {u1c, 1}}), Violation({{v, 1}})};
  const int64_t rows_before = run.rows_.store().size();
  std::vector<int32_t> attach;
  const SeparationRows::Added added =
      run.rows_.AddViolations(round, {.rows = 2}, run.set_, &attach);
  EXPECT_EQ(added.activated, 3);
  EXPECT_TRUE(added.dropped);
  EXPECT_EQ(added.full_subproblems, 1);
  const int32_t u1_part = run.set_.IdOf(run.bundles_.bundle_of(u1a));
  const int32_t v_part = run.set_.IdOf(run.bundles_.bundle_of(v));
  EXPECT_THAT(added.activated_in,
              UnorderedElementsAre(std::pair<const int32_t, int64_t>{u1_part, 2},
                                   std::pair<const int32_t, int64_t>{v_part, 1}));
  EXPECT_FALSE(added.Done(run.set_.count()));
  // The three default rows are new and to be attached; default and failsafe forms coincide
  // (all-positive rows), so nothing else was stored. The dropped row was not stored at all.
  EXPECT_EQ(attach.size(), 3u);
  EXPECT_EQ(run.rows_.store().size(), rows_before + 3);
  const LinearTerm three_u1 = {run.bundles_.bundle_of(u1a), 3};
  EXPECT_EQ(run.rows_.store().Find({&three_u1, 1}, 1), kNoId);
}

// A round is done once every subproblem is full and a violation was dropped; rows found again
// in a later round that are already active use up no cap.
TEST(SeparationRowsTest, ARoundIsDoneWhenEverySubproblemIsFullAndOneRowWasDropped) {
  IspRows run(TwoBlocksAlongU(), /*decompose=*/true, false);
  const ArcId u1 = run.Arc({0, 0, 0}, {1, 0, 0}), u1b = run.Arc({0, 1, 0}, {1, 1, 0});
  const ArcId u2 = run.Arc({1, 0, 0}, {2, 0, 0});
  const ArcId v = run.Arc({0, 0, 0}, {0, 1, 0});
  const ArcId w = run.Arc({0, 0, 0}, {0, 0, 1});
  const NewRowCap cap = {.rows = 1};
  std::vector<int32_t> attach;
  SeparationRows::Added added;
  for (ArcId a : {u1, u2, v, w}) {
    run.rows_.AddViolation(Violation({{a, 1}}), cap, run.set_, &attach, &added);
    EXPECT_FALSE(added.Done(4));
  }
  EXPECT_EQ(added.full_subproblems, 4);
  EXPECT_FALSE(added.dropped);
  run.rows_.AddViolation(Violation({{u1, 1}, {u1b, 1}}), cap, run.set_, &attach, &added);
  EXPECT_TRUE(added.dropped);
  EXPECT_TRUE(added.Done(4));
  run.set_.Attach(attach);

  // Next round: the row over u1 is active already, so the new one still fits under the cap.
  attach.clear();
  const SeparationRows::Added next = run.rows_.AddViolations(
      std::vector<SeparationViolation>{Violation({{u1, 1}}), Violation({{u1, 1}, {u1b, 1}})}, cap,
      run.set_, &attach);
  EXPECT_EQ(next.activated, 1);
  EXPECT_FALSE(next.dropped);
  EXPECT_EQ(attach.size(), 1u);
}

// The certified rows are the found paths' rows in force, in whichever form stands, never C or
// the simple rows; a failsafe twin shared by two default rows stays while either is replaced.
TEST(SeparationRowsTest, FailsafeTwinsStandInUntilTheirDefaultRowsHoldAgain) {
  IspRows run(TwoBlocksAlongU(), /*decompose=*/true, false);
  const ArcId u1 = run.Arc({0, 0, 0}, {1, 0, 0});
  const ArcId u2 = run.Arc({1, 0, 0}, {2, 0, 0});
  const ArcId v = run.Arc({0, 0, 0}, {0, 1, 0});
  std::vector<int32_t> attach = run.rows_.ActivateSimpleRows(run.set_);
  run.set_.Attach(attach);
  attach.clear();
  // q_u1 - q_u2 >= 1 and q_u1 - q_v >= 1, both with the failsafe twin q_u1 >= 1.
  run.rows_.AddViolations(
      std::vector<SeparationViolation>{Violation({{u1, 1}, {u2, -1}}, {{u1, 1}}),
                                       Violation({{u1, 1}, {v, -1}}, {{u1, 1}})},
      {.rows = 2}, run.set_, &attach);
  ASSERT_EQ(attach.size(), 2u);
  run.set_.Attach(attach);
  const int32_t minus_u2 = attach[0], minus_v = attach[1];
  const LinearTerm u1_term = {run.bundles_.bundle_of(u1), 1};
  const int32_t twin = run.rows_.store().Find({&u1_term, 1}, 1);
  ASSERT_NE(twin, kNoId);
  EXPECT_EQ(run.rows_.store().origin(twin), RowOrigin::kFailsafe);
  EXPECT_FALSE(run.rows_.store().active(twin));
  EXPECT_THAT(run.rows_.ActiveSeparationRows(), ElementsAre(minus_u2, minus_v));

  const int32_t part = run.set_.IdOf(run.bundles_.bundle_of(u1));
  const std::vector<SeparationRows::Swap> swaps = run.rows_.UseFailsafeForms(part, run.set_);
  EXPECT_THAT(swaps, UnorderedElementsAre(SeparationRows::Swap{minus_u2, twin},
                                          SeparationRows::Swap{minus_v, twin}));
  EXPECT_THAT(run.rows_.ActiveSeparationRows(), ElementsAre(twin));
  // Required rows (C, simple rows) were not swapped.
  for (int32_t r : run.set_.at(part).rows()) {
    const RowOrigin origin = run.rows_.store().origin(r);
    if (origin == RowOrigin::kBlockExtent || origin == RowOrigin::kSimple) {
      EXPECT_TRUE(run.rows_.store().active(r)) << r;
    }
  }

  // The failsafe solve moved u1 and v up by one: q_u1 - q_u2 >= 1 holds again, q_u1 - q_v >= 1
  // does not, so its twin keeps standing in.
  run.Move(run.bundles_.bundle_of(u1), 1);
  run.Move(run.bundles_.bundle_of(v), 1);
  run.rows_.RestoreDefaultForms(swaps, run.set_.at(run.set_.IdOf(run.bundles_.bundle_of(u1))));
  EXPECT_TRUE(run.rows_.store().active(minus_u2));
  EXPECT_FALSE(run.rows_.store().active(minus_v));
  EXPECT_TRUE(run.rows_.store().active(twin));
  EXPECT_THAT(run.rows_.ActiveSeparationRows(), ElementsAre(minus_u2, twin));

  // A later failsafe solve of the subproblem swaps only the default row still active. Its
  // restore must keep the twin: it still stands in for q_u1 - q_v >= 1, which q violates.
  const int32_t part_now = run.set_.IdOf(run.bundles_.bundle_of(u1));
  const std::vector<SeparationRows::Swap> second = run.rows_.UseFailsafeForms(part_now, run.set_);
  EXPECT_THAT(second, ElementsAre(SeparationRows::Swap{minus_u2, twin}));
  run.rows_.RestoreDefaultForms(second, run.set_.at(part_now));
  EXPECT_TRUE(run.rows_.store().active(minus_u2));
  EXPECT_TRUE(run.rows_.store().active(twin));
  EXPECT_THAT(run.rows_.ActiveSeparationRows(), ElementsAre(minus_u2, twin));

  // The search finds q_u1 - q_v >= 1 again, which brings its default form back; once q
  // satisfies both default rows, the next restore drops the twin.
  attach.clear();
  run.rows_.AddViolations(
      std::vector<SeparationViolation>{Violation({{u1, 1}, {v, -1}}, {{u1, 1}})}, {.rows = 2},
      run.set_, &attach);
  EXPECT_TRUE(attach.empty());
  EXPECT_TRUE(run.rows_.store().active(minus_v));
  run.Move(run.bundles_.bundle_of(u1), 1);
  const std::vector<SeparationRows::Swap> third = run.rows_.UseFailsafeForms(part_now, run.set_);
  EXPECT_EQ(third.size(), 2u);
  run.rows_.RestoreDefaultForms(third, run.set_.at(part_now));
  EXPECT_THAT(run.rows_.ActiveSeparationRows(), ElementsAre(minus_u2, minus_v));
  EXPECT_FALSE(run.rows_.store().active(twin));
}

// A found row that is also a simple row becomes required when the simple rows are activated:
// no failsafe swap touches it and the result is not certified against it as a found path.
TEST(SeparationRowsTest, AFoundRowThatIsASimpleRowBecomesRequired) {
  IspRows run(TwoBlocksAlongU(), /*decompose=*/true, false);
  // The link along the v edge at u = 0, w = 0 is one arc: its simple row is q_v >= 1.
  const ArcId v = run.Arc({0, 0, 0}, {0, 1, 0});
  EXPECT_TRUE(run.rows_.AnyHeldSimpleRowViolated());
  const int64_t violated_before = run.rows_.NumViolated();
  std::vector<int32_t> attach;
  run.rows_.AddViolations(std::vector<SeparationViolation>{Violation({{v, 1}})}, {.rows = 2},
                          run.set_, &attach);
  ASSERT_EQ(attach.size(), 1u);
  run.set_.Attach(attach);
  const int32_t found = attach[0];
  EXPECT_THAT(run.rows_.ActiveSeparationRows(), ElementsAre(found));
  // Counted once as an active row and once among the held simple rows.
  EXPECT_EQ(run.rows_.NumViolated(), violated_before + 1);

  attach = run.rows_.ActivateSimpleRows(run.set_);
  EXPECT_TRUE(run.rows_.simple_rows_active());
  EXPECT_FALSE(run.rows_.AnyHeldSimpleRowViolated());
  EXPECT_EQ(std::find(attach.begin(), attach.end(), found), attach.end()) << "not stored twice";
  run.set_.Attach(attach);
  EXPECT_TRUE(run.rows_.ActiveSeparationRows().empty());
  EXPECT_TRUE(
      run.rows_.UseFailsafeForms(run.set_.IdOf(run.bundles_.bundle_of(v)), run.set_).empty());
  EXPECT_TRUE(run.rows_.store().active(found));
}

// C holds one extent row per block axis (deduplicated over bundles), each a floor x_b >= 0 when
// it is a single bundle; the per-arc switch adds x_b >= 0 for every bundle that has none.
TEST(SeparationRowsTest, PerArcBoundsGiveEveryBundleAFloor) {
  IspRows plain(Step(), /*decompose=*/true, /*per_arc_nonnegative=*/false);
  IspRows bounded(Step(), /*decompose=*/true, /*per_arc_nonnegative=*/true);
  const int num_bundles = plain.bundles_.num_bundles();
  int plain_floors = 0, bounds = 0;
  for (uint8_t floor : plain.rows_.Floors()) plain_floors += floor;
  for (int32_t r = 0; r < bounded.rows_.store().size(); ++r) {
    const InequalityRows& store = bounded.rows_.store();
    EXPECT_TRUE(store.active(r));
    if (store.origin(r) != RowOrigin::kArcLowerBound) continue;
    ++bounds;
    ASSERT_EQ(store.terms(r).size(), 1u);
    EXPECT_EQ(store.terms(r)[0].coef, 1);
    EXPECT_EQ(store.rhs(r), 0);
    EXPECT_EQ(plain.rows_.Floors()[store.terms(r)[0].var], 0) << "had no floor before";
  }
  EXPECT_LT(plain_floors, num_bundles);
  EXPECT_EQ(bounds, num_bundles - plain_floors);
  EXPECT_EQ(bounded.rows_.store().size(), plain.rows_.store().size() + bounds);
  for (uint8_t floor : bounded.rows_.Floors()) EXPECT_EQ(floor, 1);
  for (int32_t r = 0; r < plain.rows_.store().size(); ++r) {
    EXPECT_EQ(plain.rows_.store().origin(r), RowOrigin::kBlockExtent);
  }
  // At most one extent row per block and axis; the two blocks' v extents are one bundle, so
  // one row.
  EXPECT_LE(plain.rows_.store().size(), 5);
}

}  // namespace
}  // namespace ispq
