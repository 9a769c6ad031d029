// SPDX-License-Identifier: Apache-2.0
// Bound propagation (core/isp/sheet_infeasibility.h) never refutes a request the LP can satisfy,
// and refutes many that it cannot: every root in both directions, on real and synthetic meshes,
// at a quantization moved off zero and with tight separation-like rows, answered by one LP that
// propagates first and one that does not.
#include "core/isp/sheet_infeasibility.h"

#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "core/isp/lcd_scaling.h"
#include "gtest/gtest.h"
#include "tests/bench/large/large_tmesh_generator.h"
#include "tests/support/sheet_lp_fixture.h"
#include "tests/support/test_data.h"

namespace ispq {
namespace {

using ::ispq::testing::Pump;
using ::ispq::testing::SheetLpFixture;

struct Counts {
  int64_t requests = 0, infeasible = 0, refuted = 0;
  int64_t infeasible_by_solver = 0;  // infeasible requests the LP without propagation solved
};

// Every root in both directions, in every mode, on `with` (propagation on) and `without`.
void CompareAllRequests(SheetLpFixture& with, SheetLpFixture& without, Counts* counts) {
  for (BundleId root = 0; root < with.bundles().num_bundles(); ++root) {
    for (const bool inflate : {true, false}) {
      for (const bool mixed : {true, false}) {
        SheetRequest request = Pump(root, inflate);
        request.allow_inflation = mixed || inflate;
        request.allow_deflation = mixed || !inflate;
        RationalSheet a, b;
        const int64_t refuted = with.lp().refuted_requests();
        const int64_t solver_calls = without.lp().solver_calls();
        const absl::StatusOr<bool> got = with.lp().Solve(request, &a);
        const absl::StatusOr<bool> want = without.lp().Solve(request, &b);
        ASSERT_TRUE(got.ok() && want.ok());
        ASSERT_EQ(*got, *want) << "root " << root << " inflate " << inflate << " mixed " << mixed;
        ++counts->requests;
        counts->infeasible += !*want;
        counts->refuted += with.lp().refuted_requests() - refuted;
        counts->infeasible_by_solver += !*want && without.lp().solver_calls() > solver_calls;
      }
    }
  }
}

// The same moves on both fixtures: the integer sheets the LP finds for the first roots, so that
// values, floors and slacks are not all zero.
void MoveOffZero(SheetLpFixture& a, SheetLpFixture& b, int sheets) {
  for (BundleId root = 0; root < a.bundles().num_bundles() && sheets > 0; ++root) {
    RationalSheet rational;
    const absl::StatusOr<bool> feasible = b.lp().Solve(Pump(root, true), &rational);
    ASSERT_TRUE(feasible.ok());
    if (!*feasible || LeastCommonDenominator(rational.values) != 1) continue;
    IntegerSheet sheet;
    sheet.bundles = rational.bundles;
    sheet.deltas = ScaleToIntegers(rational.values, 1);
    a.Apply(sheet);
    b.Apply(sheet);
    --sheets;
  }
}

// Rows sum x >= current value over three bundles of one axis' consistency row: tight, so that
// deflating one of them needs another to inflate, as the separation rows of a coarse level do.
void AddTightRows(SheetLpFixture& a, SheetLpFixture& b, int count, uint32_t seed) {
  std::mt19937 random(seed);
  std::vector<int32_t> ids_a, ids_b;
  for (int k = 0; k < count && a.equalities().size() > 0; ++k) {
    const auto row = a.equalities()[static_cast<int>(random() % a.equalities().size())];
    std::vector<LinearTerm> terms;
    int64_t value = 0;
    for (const LinearTerm& t : row) {
      if (std::any_of(terms.begin(), terms.end(),
                      [&](const LinearTerm& u) { return u.var == t.var; }))
        continue;
      terms.push_back({t.var, 1});
      value += a.quantization().value(t.var);
    }
    std::sort(terms.begin(), terms.end(),
              [](const LinearTerm& x, const LinearTerm& y) { return x.var < y.var; });
    if (a.rows().Find(terms, value) != kNoId) continue;
    ids_a.push_back(a.AddRow(terms, value, true));
    ids_b.push_back(b.AddRow(terms, value, true));
  }
  a.lp().AddRows(ids_a);
  b.lp().AddRows(ids_b);
}

struct Case {
  std::string name;
  std::function<TMesh()> mesh;
};

class SheetInfeasibilityTest : public ::testing::TestWithParam<Case> {};

TEST_P(SheetInfeasibilityTest, RefutesOnlyInfeasibleRequests) {
  const TMesh mesh = GetParam().mesh();
  Counts counts;
  for (const Level& level : {mesh.levels().front(), mesh.levels().back()}) {
    SCOPED_TRACE(level.percent);
    SheetLpFixture with(mesh, level.scaling);
    SheetLpFixture without(mesh, level.scaling, {.refute_by_propagation = false});
    CompareAllRequests(with, without, &counts);
    MoveOffZero(with, without, 20);
    CompareAllRequests(with, without, &counts);
    AddTightRows(with, without, 40, 7);
    CompareAllRequests(with, without, &counts);
  }
  // The comparison means something only if both answers occurred and propagation took part.
  EXPECT_GT(counts.requests - counts.infeasible, counts.requests / 10);
  EXPECT_GT(counts.refuted, counts.infeasible_by_solver / 2)
      << counts.requests << " requests, " << counts.infeasible << " infeasible, "
      << counts.infeasible_by_solver << " of them by the solver";
}

INSTANTIATE_TEST_SUITE_P(
    Meshes, SheetInfeasibilityTest,
    ::testing::Values(Case{"notch",
                           [] {
                             return testing::LoadTMeshOrDie(
                                 testing::RealTMeshPath("hex-me/s07c_notch.tmesh.json"));
                           }},
                      Case{"cube_corner_sub_sphere",
                           [] {
                             return testing::LoadTMeshOrDie(
                                 testing::RealTMeshDir() +
                                 "/hex-me/s14b_cube_corner_sub_sphere.tmesh.json");
                           }},
                      Case{"large_single_1000",
                           [] {
                             const absl::StatusOr<testing::GridTMesh> grid = bench::BuildLargeTMesh(
                                 bench::LargeFamily::kSingleSubproblem, 1000, 3);
                             return testing::TMeshOrDie(grid->proto());
                           }}),
    [](const auto& info) { return info.param.name; });

}  // namespace
}  // namespace ispq
