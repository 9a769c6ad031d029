// SPDX-License-Identifier: Apache-2.0
// The per-subproblem sheet LP: a sheet on a single cube, floors, separating (self-inflating)
// solves, and the half-integral U-turn of the paper's Figs. 6 and 7.
#include "core/isp/sheet_subproblem.h"

#include <memory>
#include <vector>

#include "core/isp/lcd_scaling.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "tests/support/grid_tmesh_builder.h"
#include "tests/support/sheet_lp_fixture.h"
#include "tests/support/test_data.h"
#include "tests/support/worked_examples.h"

namespace ispq {
namespace {

using ::testing::ElementsAre;
using ::testing::Optional;

using ::ispq::testing::Pump;
using ::ispq::testing::SheetLpFixture;

TEST(SheetSubproblemTest, SheetOnASingleCubeIsOneAxisLayer) {
  const TMesh mesh = testing::LoadTMeshOrDie(testing::RealTMeshPath("hex-me/s01c_cube.tmesh.json"));
  SheetLpFixture fixture(mesh, 0.05);
  ASSERT_EQ(fixture.bundles().num_bundles(), 3);
  for (BundleId root = 0; root < 3; ++root) {
    RationalSheet sheet;
    const absl::StatusOr<bool> feasible = fixture.lp().Solve(Pump(root, true), &sheet);
    ASSERT_TRUE(feasible.ok()) << feasible.status();
    ASSERT_TRUE(*feasible);
    EXPECT_THAT(sheet.bundles, ElementsAre(root));
    EXPECT_THAT(sheet.values, ElementsAre(::testing::DoubleNear(1, 1e-9)));
  }
}

TEST(SheetSubproblemTest, FloorsBlockDeflationBelowZeroWithoutTheSolver) {
  const TMesh mesh = testing::LoadTMeshOrDie(testing::RealTMeshPath("hex-me/s01c_cube.tmesh.json"));
  SheetLpFixture fixture(mesh, 0.05);
  RationalSheet sheet;
  const int64_t calls = fixture.lp().solver_calls();
  absl::StatusOr<bool> feasible = fixture.lp().Solve(Pump(1, false), &sheet);
  ASSERT_TRUE(feasible.ok());
  EXPECT_FALSE(*feasible);
  EXPECT_EQ(fixture.lp().solver_calls(), calls);

  IntegerSheet up;
  up.bundles = {1};
  up.deltas = {2};
  fixture.Apply(up);
  feasible = fixture.lp().Solve(Pump(1, false), &sheet);
  ASSERT_TRUE(feasible.ok());
  ASSERT_TRUE(*feasible);
  EXPECT_THAT(sheet.bundles, ElementsAre(1));
  EXPECT_THAT(sheet.values, ElementsAre(::testing::DoubleNear(-1, 1e-9)));
}

TEST(SheetSubproblemTest, AnAppendedRowBoundsDeflation) {
  const TMesh mesh = testing::LoadTMeshOrDie(testing::RealTMeshPath("hex-me/s01c_cube.tmesh.json"));
  SheetLpFixture fixture(mesh, 0.05, {.extent_rows = false});
  // Without C rows nothing stops a deflation below 0...
  RationalSheet sheet;
  absl::StatusOr<bool> feasible = fixture.lp().Solve(Pump(0, false), &sheet);
  ASSERT_TRUE(feasible.ok());
  EXPECT_TRUE(*feasible);
  // ...until a row x_0 >= 0 is appended.
  const int32_t r = fixture.AddRow({{0, 1}}, 0, true);
  const std::vector<int32_t> added = {r};
  fixture.lp().AddRows(added);
  feasible = fixture.lp().Solve(Pump(0, false), &sheet);
  ASSERT_TRUE(feasible.ok());
  EXPECT_FALSE(*feasible);
}

TEST(SheetSubproblemTest, ViolatedRowsInflateASeparatingSheet) {
  const TMesh mesh = testing::LoadTMeshOrDie(testing::RealTMeshPath("hex-me/s01c_cube.tmesh.json"));
  SheetLpFixture fixture(mesh, 0.05);
  // x_0 + x_2 >= 1 and x_2 - x_1 >= 1 at q = 0: the cheapest fix inflates bundle 2 alone.
  const std::vector<int32_t> added = {fixture.AddRow({{0, 1}, {2, 1}}, 1, true),
                                      fixture.AddRow({{1, -1}, {2, 1}}, 1, true)};
  fixture.lp().AddRows(added);
  EXPECT_EQ(fixture.rows().num_violated_active(), 2);
  RationalSheet sheet;
  SheetRequest request;  // no root: the rows pump the sheet
  const absl::StatusOr<bool> feasible = fixture.lp().Solve(request, &sheet);
  ASSERT_TRUE(feasible.ok());
  ASSERT_TRUE(*feasible);
  EXPECT_THAT(sheet.bundles, ElementsAre(2));
  EXPECT_THAT(sheet.values, ElementsAre(::testing::DoubleNear(1, 1e-9)));
  // Once it is applied nothing is violated and the LP has nothing to do.
  IntegerSheet sheet2;
  sheet2.bundles = {2};
  sheet2.deltas = {1};
  fixture.Apply(sheet2);
  EXPECT_EQ(fixture.rows().num_violated_active(), 0);
  const absl::StatusOr<bool> again = fixture.lp().Solve(request, &sheet);
  ASSERT_TRUE(again.ok());
  ASSERT_TRUE(*again);
  EXPECT_TRUE(sheet.bundles.empty());
}

TEST(SheetSubproblemTest, IsConsistentChecksIntegerSheetsExactly) {
  // The notch has T-junctions, hence consistency rows that bundling does not eliminate.
  const TMesh mesh =
      testing::LoadTMeshOrDie(testing::RealTMeshPath("hex-me/s07c_notch.tmesh.json"));
  SheetLpFixture fixture(mesh, 0.2);
  RationalSheet rational;
  const absl::StatusOr<bool> feasible = fixture.lp().Solve(Pump(0, true), &rational);
  ASSERT_TRUE(feasible.ok());
  ASSERT_TRUE(*feasible);
  const std::optional<int64_t> lcd = LeastCommonDenominator(rational.values);
  ASSERT_TRUE(lcd.has_value());
  IntegerSheet sheet;
  sheet.bundles = rational.bundles;
  sheet.deltas = ScaleToIntegers(rational.values, *lcd);
  EXPECT_TRUE(fixture.lp().IsConsistent(sheet));
  // One bundle of a consistency row moving alone breaks that row.
  ASSERT_GT(fixture.equalities().size(), 0);
  IntegerSheet alone;
  alone.bundles = {fixture.equalities()[0][0].var};
  alone.deltas = {1};
  EXPECT_FALSE(fixture.lp().IsConsistent(alone));
}

// The finite column cap only speeds up the solver: with a cap every solution reaches (0.5, below
// the root's pump bound) or some may (1.5), every root in both directions gets the answer it
// gets without a cap, because such solves are repeated without it.
TEST(SheetSubproblemTest, ColumnCapNeverChangesAnAnswer) {
  const TMesh mesh =
      testing::LoadTMeshOrDie(testing::RealTMeshPath("hex-me/s07c_notch.tmesh.json"));
  SheetLpFixture uncapped(mesh, 0.2, {.column_cap = kLpInfinity});
  for (const double cap : {0.5, 1.5, SheetLpContext{}.column_cap}) {
    SCOPED_TRACE(cap);
    SheetLpFixture capped(mesh, 0.2, {.column_cap = cap});
    int64_t feasible_solves = 0;
    for (BundleId root = 0; root < capped.bundles().num_bundles(); ++root) {
      for (const bool inflate : {true, false}) {
        RationalSheet expected, sheet;
        const absl::StatusOr<bool> want = uncapped.lp().Solve(Pump(root, inflate), &expected);
        const absl::StatusOr<bool> got = capped.lp().Solve(Pump(root, inflate), &sheet);
        ASSERT_TRUE(want.ok() && got.ok());
        ASSERT_EQ(*got, *want) << "root " << root << " inflate " << inflate;
        if (!*got) continue;
        ++feasible_solves;
        EXPECT_EQ(sheet.bundles, expected.bundles) << "root " << root << " inflate " << inflate;
        EXPECT_THAT(sheet.values,
                    ::testing::Pointwise(::testing::DoubleNear(1e-9), expected.values));
      }
    }
    EXPECT_GT(feasible_solves, capped.bundles().num_bundles());
    EXPECT_EQ(uncapped.lp().uncapped_solves(), 0);
    if (cap < 1) {
      EXPECT_EQ(capped.lp().uncapped_solves(), capped.lp().solver_calls() / 2);
    }
  }
}

// Paper Figs. 6/7: forcing the root through a U-turn of T-junctions yields halves.
TEST(SheetSubproblemTest, UTurnOfTJunctionsGivesAHalfIntegralSheet) {
  const testing::HalfIntegerSheetExample example = testing::MakeHalfIntegerSheetExample();
  const absl::StatusOr<testing::GridTMesh> grid = testing::BuildGridTMesh(example.spec);
  ASSERT_TRUE(grid.ok()) << grid.status();
  const TMesh mesh = testing::TMeshOrDie(grid->proto());
  SheetLpFixture fixture(mesh, 1.0);
  const ArcId root_arc = grid->ArcBetween(example.root.first, example.root.second);
  ASSERT_GE(root_arc, 0);
  SheetRequest request = Pump(fixture.bundles().bundle_of(root_arc), true);
  request.allow_deflation = false;  // eq. 2: Delta q >= 0
  RationalSheet sheet;
  const absl::StatusOr<bool> feasible = fixture.lp().Solve(request, &sheet);
  ASSERT_TRUE(feasible.ok()) << feasible.status();
  ASSERT_TRUE(*feasible);
  EXPECT_THAT(LeastCommonDenominator(sheet.values), Optional(2));
  // Every half-arc of the example carries 1/2.
  for (const auto& [from, to] : example.half_arcs) {
    const BundleId b = fixture.bundles().bundle_of(grid->ArcBetween(from, to));
    const auto it = std::find(sheet.bundles.begin(), sheet.bundles.end(), b);
    ASSERT_NE(it, sheet.bundles.end());
    EXPECT_NEAR(sheet.values[it - sheet.bundles.begin()], 0.5, 1e-9);
  }
}

}  // namespace
}  // namespace ispq
