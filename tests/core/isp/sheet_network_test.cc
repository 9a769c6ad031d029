// SPDX-License-Identifier: Apache-2.0
// Sheet LPs without a root solved as flows (core/isp/sheet_network.h), side by side with the LP
// on the same subproblem: the same optimum for the bulk descent's unit moves and for separating
// requests, integer answers, and rows over more than two potentials kept by splitting; on parts
// with handles a restriction of the LP, which confirms a descent the flow cannot continue.
#include "core/isp/sheet_network.h"

#include <cmath>
#include <cstdint>
#include <vector>

#include "core/isp/sheet_subproblem.h"
#include "core/isp/sheet_weights.h"
#include "gtest/gtest.h"
#include "tests/bench/large/large_tmesh_generator.h"
#include "tests/support/grid_tmesh_builder.h"
#include "tests/support/sheet_lp_fixture.h"
#include "tests/support/test_data.h"

namespace ispq {
namespace {

using ::ispq::testing::SheetLpFixture;

// An assembly part of ~3000 arcs: global frames, no handle, T-junctions everywhere.
TMesh AssemblyPart() {
  const absl::StatusOr<testing::GridTMesh> grid =
      bench::BuildLargeTMesh(bench::LargeFamily::kAssembly16, 3000, 5);
  EXPECT_TRUE(grid.ok()) << grid.status();
  return testing::TMeshOrDie(grid->proto());
}

SheetRequest Request(WeightScheme weights, bool unit_moves, bool inflation, bool deflation) {
  SheetRequest request;
  request.weights = weights;
  request.unit_moves = unit_moves;
  request.allow_inflation = inflation;
  request.allow_deflation = deflation;
  return request;
}

BundleWeights WeightsAt(const BundleQuantization& x, BundleId b, WeightScheme scheme) {
  const double value = static_cast<double>(x.value(b));
  return scheme == WeightScheme::kUnitCost ? BundleUnitCosts(x.targets(b), value)
                                           : BundleMarginalWeights(x.targets(b), value, 1e-3);
}

// The LP objective of a sheet.
double Cost(const BundleQuantization& x, const RationalSheet& sheet, WeightScheme scheme) {
  double cost = 0;
  for (size_t i = 0; i < sheet.bundles.size(); ++i) {
    const BundleWeights w = WeightsAt(x, sheet.bundles[i], scheme);
    const double v = sheet.values[i];
    cost += v > 0 ? w.inflate * v : -w.deflate * v;
  }
  return cost;
}

// The sheet as integers; fails the test if it has a fractional value.
IntegerSheet AsIntegers(const RationalSheet& sheet) {
  IntegerSheet integer;
  integer.bundles = sheet.bundles;
  for (const double v : sheet.values) {
    EXPECT_EQ(v, std::round(v));
    integer.deltas.push_back(static_cast<int64_t>(std::round(v)));
  }
  return integer;
}

// Both fixtures' answers to one request: their costs, and whether the flow answered (else the
// flow fixture's LP did).
struct BothAnswers {
  double flow_cost, lp_cost;
  bool by_flow;
};

// Solves `request` on both fixtures; expects both feasible, the flow fixture's answer an integer
// sheet the consistency rows accept.
BothAnswers SolveBoth(SheetLpFixture& flow, SheetLpFixture& lp, const SheetRequest& request,
                      RationalSheet* flow_sheet) {
  RationalSheet lp_sheet;
  const int64_t flow_solves = flow.lp().flow_solves();
  const absl::StatusOr<bool> by_flow = flow.lp().Solve(request, flow_sheet);
  const absl::StatusOr<bool> by_lp = lp.lp().Solve(request, &lp_sheet);
  EXPECT_TRUE(by_flow.ok() && by_lp.ok());
  EXPECT_TRUE(*by_flow && *by_lp);
  EXPECT_EQ(lp.lp().flow_solves(), 0);
  EXPECT_TRUE(flow.lp().IsConsistent(AsIntegers(*flow_sheet)));
  return {Cost(flow.quantization(), *flow_sheet, request.weights),
          Cost(lp.quantization(), lp_sheet, request.weights),
          flow.lp().flow_solves() == flow_solves + 1};
}

TEST(SheetNetworkTest, UnitMovesCostWhatTheLpsOptimumCosts) {
  const TMesh mesh = AssemblyPart();
  const double scaling = mesh.levels()[5].scaling;
  SheetLpFixture flow(mesh, scaling, {.flows = true});
  SheetLpFixture lp(mesh, scaling);
  // A descent of both fixtures along the flow's steps, in the three modes.
  int improving = 0;
  for (int step = 0; step < 12; ++step) {
    SCOPED_TRACE(step);
    const bool inflation = step % 3 != 2, deflation = step % 3 != 1;
    RationalSheet sheet;
    const auto [flow_cost, lp_cost, by_flow] =
        SolveBoth(flow, lp, Request(WeightScheme::kUnitCost, true, inflation, deflation), &sheet);
    EXPECT_TRUE(by_flow);
    EXPECT_NEAR(flow_cost, lp_cost, 1e-6 * (1 + std::abs(lp_cost)));
    for (const double v : sheet.values) {
      EXPECT_LE(v, inflation ? 1 : 0);
      EXPECT_GE(v, deflation ? -1 : 0);
    }
    if (flow_cost >= -1e-9) continue;
    ++improving;
    const IntegerSheet moves = AsIntegers(sheet);
    flow.Apply(moves);
    lp.Apply(moves);
    EXPECT_EQ(flow.rows().num_violated_active(), 0);
  }
  EXPECT_GT(improving, 2);
}

TEST(SheetNetworkTest, SeparatingRequestsCostWhatTheLpsOptimumCosts) {
  const TMesh mesh = AssemblyPart();
  const double scaling = mesh.levels()[5].scaling;
  SheetLpFixture flow(mesh, scaling, {.flows = true});
  SheetLpFixture lp(mesh, scaling);
  // Rows over one bundle each (two potentials: difference rows), violated by 1-3 units.
  for (const BundleId b : {BundleId{0}, BundleId{7}, BundleId{21}}) {
    for (SheetLpFixture* fixture : {&flow, &lp}) {
      const int32_t r =
          fixture->AddRow({{b, 1}}, fixture->quantization().value(b) + 1 + b % 3, true);
      const std::vector<int32_t> added = {r};
      fixture->lp().AddRows(added);
    }
  }
  for (const bool deflation : {true, false}) {
    SCOPED_TRACE(deflation);
    RationalSheet sheet;
    const auto [flow_cost, lp_cost, by_flow] =
        SolveBoth(flow, lp, Request(WeightScheme::kMarginalCost, false, true, deflation), &sheet);
    EXPECT_TRUE(by_flow);
    EXPECT_NEAR(flow_cost, lp_cost, 1e-6 * (1 + std::abs(lp_cost)));
  }
}

TEST(SheetNetworkTest, ARowOverFourPotentialsIsKeptBySplittingIt) {
  const TMesh mesh = AssemblyPart();
  const double scaling = mesh.levels()[5].scaling;
  const ConsistencyMatrix consistency(mesh);
  const ArcBundles bundles(mesh, consistency);
  const std::optional<BundlePotentials> potentials =
      BundlePotentials::Compute(mesh, consistency, bundles);
  ASSERT_TRUE(potentials.has_value());
  // Two bundles with four different potentials: x_a + x_b >= values + 1 is no difference row.
  const BundleId a = 0;
  BundleId b = 1;
  const auto shares = [&](BundleId c) {
    for (const int32_t p : {potentials->tail(c), potentials->head(c)}) {
      if (p == potentials->tail(a) || p == potentials->head(a)) return true;
    }
    return false;
  };
  while (shares(b)) ++b;
  SheetLpFixture flow(mesh, scaling, {.flows = true});
  SheetLpFixture lp(mesh, scaling);
  int32_t row = kNoId;
  for (SheetLpFixture* fixture : {&flow, &lp}) {
    const BundleQuantization& x = fixture->quantization();
    row = fixture->AddRow({{a, 1}, {b, 1}}, x.value(a) + x.value(b) + 1, true);
    const std::vector<int32_t> added = {row};
    fixture->lp().AddRows(added);
  }
  for (const bool unit_moves : {true, false}) {
    SCOPED_TRACE(unit_moves);
    const WeightScheme scheme = unit_moves ? WeightScheme::kUnitCost : WeightScheme::kMarginalCost;
    RationalSheet sheet;
    const auto [flow_cost, lp_cost, by_flow] =
        SolveBoth(flow, lp, Request(scheme, unit_moves, true, true), &sheet);
    EXPECT_TRUE(by_flow);
    // A restriction of the LP: never cheaper than its optimum, and the row holds.
    EXPECT_GE(flow_cost, lp_cost - 1e-6 * (1 + std::abs(lp_cost)));
    int64_t change = 0;
    const IntegerSheet moves = AsIntegers(sheet);
    for (size_t i = 0; i < moves.bundles.size(); ++i) {
      for (const LinearTerm& t : flow.rows().terms(row)) {
        if (t.var == moves.bundles[i]) change += t.coef * moves.deltas[i];
      }
    }
    EXPECT_GE(change, -flow.rows().slack(row));
  }
}

TEST(SheetNetworkTest, AroundAHoleTheFlowHoldsThePeriods) {
  // A ring of eight blocks around a hole: the hole's two sides along an axis are bundles of their
  // own, tied only by a period. A row that makes one side grow is kept by the flow, at P = 0, by
  // growing the other side too: feasible, and dearer than the LP, which moves the period.
  const TMesh mesh =
      testing::TMeshOrDie(testing::BuildGridTMeshOrDie(testing::RingAroundAHole()).proto());
  const ConsistencyMatrix consistency(mesh);
  const ArcBundles bundles(mesh, consistency);
  const std::optional<BundlePotentials> potentials =
      BundlePotentials::Compute(mesh, consistency, bundles);
  ASSERT_TRUE(potentials.has_value());
  ASSERT_TRUE(potentials->has_handles());
  const double scaling = mesh.levels()[3].scaling;
  int checked = 0, dearer = 0;
  for (BundleId b = 0; b < bundles.num_bundles(); ++b) {
    // The sides of the hole: bundles between the same two potentials as another.
    bool side = false;
    for (BundleId c = 0; c < bundles.num_bundles(); ++c) {
      side = side || (c != b && potentials->tail(c) == potentials->tail(b) &&
                      potentials->head(c) == potentials->head(b));
    }
    if (!side) continue;
    SCOPED_TRACE(b);
    SheetLpFixture flow(mesh, scaling, {.flows = true});
    SheetLpFixture lp(mesh, scaling);
    for (SheetLpFixture* fixture : {&flow, &lp}) {
      const int32_t r = fixture->AddRow({{b, 1}}, fixture->quantization().value(b) + 1, true);
      const std::vector<int32_t> added = {r};
      fixture->lp().AddRows(added);
    }
    RationalSheet sheet;
    const auto [flow_cost, lp_cost, by_flow] =
        SolveBoth(flow, lp, Request(WeightScheme::kMarginalCost, false, true, true), &sheet);
    EXPECT_TRUE(by_flow);
    EXPECT_GE(flow_cost, lp_cost - 1e-6 * (1 + std::abs(lp_cost)));
    dearer += flow_cost > lp_cost + 1e-6 * (1 + std::abs(lp_cost));
    ++checked;
  }
  EXPECT_EQ(checked, 4);
  EXPECT_EQ(dearer, 4);
}

TEST(SheetNetworkTest, OnAPartWithHandlesTheDescentStopsWhereTheLpsDoes) {
  // A part with through holes (the single family): the flow, holding the periods, answers the
  // descent's steps while it finds one that descends, never cheaper than the LP's optimum; where
  // it finds none the LP answers if the request asks it to confirm (the pump's thorough pass), so
  // the descent stops only where the LP finds no step either.
  const absl::StatusOr<testing::GridTMesh> grid =
      bench::BuildLargeTMesh(bench::LargeFamily::kSingleSubproblem, 3000, 5);
  ASSERT_TRUE(grid.ok()) << grid.status();
  const TMesh mesh = testing::TMeshOrDie(grid->proto());
  const double scaling = mesh.levels()[5].scaling;
  SheetLpFixture flow(mesh, scaling, {.flows = true});
  SheetLpFixture lp(mesh, scaling);
  int answered_by_flow = 0, answered_by_lp = 0, idle = 0;
  for (int step = 0; step < 60 && idle < 3; ++step) {
    SCOPED_TRACE(step);
    const bool inflation = step % 3 != 2, deflation = step % 3 != 1;
    RationalSheet sheet;
    SheetRequest request = Request(WeightScheme::kUnitCost, true, inflation, deflation);
    request.confirm_stalled_flow = true;
    const auto [flow_cost, lp_cost, by_flow] = SolveBoth(flow, lp, request, &sheet);
    const double tolerance = 1e-6 * (1 + std::abs(lp_cost));
    EXPECT_GE(flow_cost, lp_cost - tolerance);
    if (by_flow) {
      ++answered_by_flow;
      EXPECT_LT(flow_cost, 0);
    } else {
      ++answered_by_lp;
      EXPECT_NEAR(flow_cost, lp_cost, tolerance);
    }
    for (const double v : sheet.values) {
      EXPECT_LE(v, inflation ? 1 : 0);
      EXPECT_GE(v, deflation ? -1 : 0);
    }
    if (flow_cost >= -1e-9) {
      EXPECT_GE(lp_cost, -tolerance);
      ++idle;
      continue;
    }
    idle = 0;
    const IntegerSheet moves = AsIntegers(sheet);
    flow.Apply(moves);
    lp.Apply(moves);
    EXPECT_EQ(flow.rows().num_violated_active(), 0);
  }
  EXPECT_EQ(idle, 3);  // no step in any mode, by the LP's word
  EXPECT_GT(answered_by_flow, 2);
  EXPECT_GT(answered_by_lp, 2);
  // Unasked, the flow answers where it stalls.
  RationalSheet sheet;
  EXPECT_TRUE(
      SolveBoth(flow, lp, Request(WeightScheme::kUnitCost, true, true, true), &sheet).by_flow);
}

}  // namespace
}  // namespace ispq
