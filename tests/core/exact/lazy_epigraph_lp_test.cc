// SPDX-License-Identifier: Apache-2.0
// The lazy secant LP on a box whose relaxation optimum is known by hand, from the secants around
// the optimum and from far away, within windows that do and do not hold the optimum, and equal to
// the full relaxation on a T-junction. (tests/core/exact/lower_bound_test.cc compares it
// with the full relaxation on real meshes.)
#include "core/exact/lazy_epigraph_lp.h"

#include <cmath>
#include <cstdint>
#include <optional>
#include <vector>

#include "core/arc_bundles.h"
#include "core/consistency_matrix.h"
#include "core/exact/bundle_objective.h"
#include "core/exact/cbc_milp_solver.h"
#include "core/exact/milp_solver.h"
#include "core/exact/quantization_constraints.h"
#include "core/exact/quantization_milp.h"
#include "core/tmesh.h"
#include "gtest/gtest.h"
#include "tests/support/grid_tmesh_builder.h"
#include "tests/support/test_data.h"

namespace ispq {
namespace {

struct Problem {
  Problem(const testing::GridTMeshSpec& spec, double scaling)
      : mesh(testing::TMeshOrDie(testing::BuildGridTMesh(spec)->proto())),
        consistency(mesh),
        bundles(mesh, consistency),
        objectives(mesh, bundles, scaling),
        constraints(mesh, consistency, bundles, false) {}
  TMesh mesh;
  ConsistencyMatrix consistency;
  ArcBundles bundles;
  BundleObjectives objectives;
  QuantizationConstraints constraints;
};

// One block with targets 2.3, 3.6 and 0.7 along u, v, w (bundles 0, 1, 2), four arcs each:
// f_b(x) = 4 (x - t_b)^2. The relaxation minimizes the piecewise-linear interpolation of each f_b
// through the integers, subject to the links x_b >= 1: its optimum is at the rounded targets
// (2, 4, 1), 4 (0.09 + 0.16 + 0.09) = 1.36.
testing::GridTMeshSpec Box() {
  testing::GridTMeshSpec spec;
  spec.blocks = {{{0, 0, 0}, {1, 1, 1}}};
  spec.spacing = {std::vector<double>{2.3}, std::vector<double>{3.6}, std::vector<double>{0.7}};
  return spec;
}

std::vector<IntegerWindow> Windows(int64_t lo, int64_t hi) {
  return std::vector<IntegerWindow>(3, IntegerWindow{lo, hi});
}

TEST(LazyEpigraphLpTest, FromTheOptimumItsOwnSecantsSuffice) {
  const Problem p(Box(), 1.0);
  const std::optional<double> value = SolveLazyEpigraphRelaxation(
      p.objectives, p.constraints, Windows(0, 8), std::vector<int64_t>{2, 4, 1});
  ASSERT_TRUE(value.has_value());
  EXPECT_NEAR(*value, 1.36, 1e-9);
}

// Starting far from the optimum, the secants the solutions violate join until none does.
TEST(LazyEpigraphLpTest, FromFarAwayTheSecantsFollowTheSolution) {
  const Problem p(Box(), 1.0);
  for (const std::vector<int64_t>& x : {std::vector<int64_t>{7, 1, 5}, {1, 8, 8}, {8, 8, 1}}) {
    const std::optional<double> value =
        SolveLazyEpigraphRelaxation(p.objectives, p.constraints, Windows(0, 8), x);
    ASSERT_TRUE(value.has_value());
    EXPECT_NEAR(*value, 1.36, 1e-9) << x[0] << "," << x[1] << "," << x[2];
  }
}

// A window that excludes the optimum bounds x_v: v >= 6 costs 4 * 2.4^2 = 23.04 instead of 0.64.
TEST(LazyEpigraphLpTest, TheWindowsBoundTheBundles) {
  const Problem p(Box(), 1.0);
  std::vector<IntegerWindow> windows = Windows(0, 8);
  windows[1] = {6, 8};
  const std::optional<double> value =
      SolveLazyEpigraphRelaxation(p.objectives, p.constraints, windows, {{2, 7, 1}});
  ASSERT_TRUE(value.has_value());
  EXPECT_NEAR(*value, 0.36 + 23.04 + 0.36, 1e-9);
}

// Two half-width blocks on a full-width one (u_full = u_left + u_right): from a known q near the
// targets and from one far above them, the lazy LP ends at the optimum of the full relaxation
// (every secant of every window, solved by CLP), never above the known q's objective.
TEST(LazyEpigraphLpTest, EqualsTheFullRelaxation) {
  testing::GridLayout2D layout;
  layout.blocks = {{{0, 0}, {2, 1}}, {{0, 1}, {1, 2}}, {{1, 1}, {2, 2}}};
  layout.spacing = {std::vector<double>{1.4, 1.4}, std::vector<double>{1.0, 1.0}};
  const testing::GridTMeshSpec spec = testing::ExtrudeLayout(layout);
  const testing::GridTMesh grid = *testing::BuildGridTMesh(spec);
  for (double scaling : {0.6, 1.25, 2.2}) {
    const Problem p(spec, scaling);
    const BundleId full = p.bundles.bundle_of(grid.ArcBetween({0, 0, 0}, {2, 0, 0}));
    for (int64_t k : {1, 4}) {
      SCOPED_TRACE(::testing::PrintToString(scaling) + " from " + ::testing::PrintToString(k));
      std::vector<int64_t> x(p.bundles.num_bundles(), k);
      x[full] = 2 * k;
      ASSERT_TRUE(p.constraints.SatisfiesFixedRows(x));
      const absl::StatusOr<QuantizationMilp> milp =
          BuildQuantizationMilp(p.objectives, p.constraints, x);
      ASSERT_TRUE(milp.ok()) << milp.status();
      const absl::StatusOr<LpResult> relaxation = NewCbcMilpSolver()->SolveRelaxation(milp->model);
      ASSERT_TRUE(relaxation.ok() && relaxation->status == LpStatus::kOptimal);
      const std::optional<double> lazy = SolveLazyEpigraphRelaxation(
          p.objectives, p.constraints, ModelWindows(p.objectives, p.constraints, x), x);
      ASSERT_TRUE(lazy.has_value());
      EXPECT_NEAR(*lazy, relaxation->objective, 1e-7 * (1 + std::abs(relaxation->objective)));
      EXPECT_LE(*lazy, p.objectives.Objective(x) + 1e-9);
    }
  }
}

}  // namespace
}  // namespace ispq
