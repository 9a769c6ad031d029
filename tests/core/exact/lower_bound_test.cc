// SPDX-License-Identifier: Apache-2.0
// The lower bound of a result (core/exact/lower_bound.h): never above the objective or the true
// optimum, equal to the optimum where the LP relaxation is integral, strictly below where it is
// not, and attached to results as the options ask. Its LP with secants added as needed
// (core/exact/lazy_epigraph_lp.h) has the optimum of the full relaxation.
#include "core/exact/lower_bound.h"

#include <cmath>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/arc_bundles.h"
#include "core/consistency_matrix.h"
#include "core/exact/bundle_objective.h"
#include "core/exact/cbc_milp_solver.h"
#include "core/exact/lazy_epigraph_lp.h"
#include "core/exact/quantization_constraints.h"
#include "core/exact/quantization_milp.h"
#include "core/quantizer.h"
#include "gtest/gtest.h"
#include "tests/support/enumerated_optimum.h"
#include "tests/support/grid_tmesh_builder.h"
#include "tests/support/test_data.h"

namespace ispq {
namespace {

TMesh RealMesh(const std::string& model) {
  for (const std::string& file : testing::RealTMeshFiles()) {
    if (testing::ShortName(file).ends_with("/" + model)) return testing::LoadTMeshOrDie(file);
  }
  ADD_FAILURE() << "no real mesh " << model;
  return testing::TMeshOrDie(v1::TMesh());
}

QuantizeResult QuantizeOrDie(const TMesh& mesh, const QuantizeOptions& options) {
  absl::StatusOr<QuantizeResult> result = Quantize(mesh, options);
  EXPECT_TRUE(result.ok()) << result.status();
  return *std::move(result);
}

TEST(LowerBoundTest, RelativeGap) {
  EXPECT_EQ(RelativeGap(0, 0), 0);
  EXPECT_NEAR(RelativeGap(10, 9), 0.1, 1e-12);
  EXPECT_EQ(RelativeGap(10, 10 - 1e-12), 0);
  EXPECT_EQ(RelativeGap(10, 11), 0);
  EXPECT_EQ(RelativeGap(2, 0), 1);
}

// Every ISP result on five small real meshes carries a bound at most its objective, and the gap
// that goes with it.
TEST(LowerBoundTest, IspResultsOfTheSamplesCarryABoundBelowTheirObjective) {
  for (const char* file : {"hex-me/s01c_cube.tmesh.json", "hex-me/s02c_prism.tmesh.json",
                           "hex-me/s04u_tetrahedron.tmesh.json", "hex-me/s07c_notch.tmesh.json",
                           "singularity-constrained-fields/fanpart.tmesh.json"}) {
    const TMesh mesh = testing::LoadTMeshOrDie(testing::RealTMeshPath(file));
    for (const Level& level : mesh.levels()) {
      QuantizeOptions options;
      options.scaling = level.scaling;
      const QuantizeResult result = QuantizeOrDie(mesh, options);
      ASSERT_TRUE(result.valid);
      ASSERT_TRUE(result.lower_bound.has_value()) << file;
      ASSERT_TRUE(result.gap.has_value());
      EXPECT_LE(*result.lower_bound, result.objective);
      EXPECT_GE(*result.gap, 0);
      EXPECT_LE(*result.gap, 1);
      EXPECT_EQ(*result.gap, RelativeGap(result.objective, *result.lower_bound));
    }
  }
}

// Where the relaxation is integral (a planar T-junction layout: its consistency matrix is
// totally unimodular) the bound is the brute-force optimum itself.
TEST(LowerBoundTest, EqualsTheOptimumWhereTheRelaxationIsIntegral) {
  testing::GridLayout2D layout;
  layout.blocks = {{{0, 0}, {2, 1}}, {{0, 1}, {1, 2}}, {{1, 1}, {2, 2}}};
  layout.spacing = {std::vector<double>{1.4, 1.4}, std::vector<double>{1.0, 1.0}};
  const TMesh mesh =
      testing::TMeshOrDie(testing::BuildGridTMesh(testing::ExtrudeLayout(layout))->proto());
  for (double scaling : {1.0, 1.3, 2.2, 3.7}) {
    const absl::StatusOr<testing::EnumeratedOptimum> optimum =
        testing::EnumerateOptimum(mesh, scaling, 1);
    ASSERT_TRUE(optimum.ok());
    const std::unique_ptr<MilpSolver> solver = NewCbcMilpSolver();
    QuantizeOptions options;
    options.scaling = scaling;
    const absl::StatusOr<double> bound = ComputeLowerBound(mesh, options, optimum->q, {}, *solver);
    ASSERT_TRUE(bound.ok()) << bound.status();
    EXPECT_NEAR(*bound, optimum->objective, 1e-6) << scaling;
  }
}

// s09c_bridge at level 100: the relaxation is fractional, so the bound lies strictly below ISP's
// objective, and still below the optimum that exact mode proves.
TEST(LowerBoundTest, StaysBelowTheOptimumWhereTheRelaxationIsFractional) {
  const TMesh mesh = RealMesh("s09c_bridge");
  QuantizeOptions options;
  options.scaling = mesh.levels().back().scaling;
  const QuantizeResult isp = QuantizeOrDie(mesh, options);
  ASSERT_TRUE(isp.lower_bound.has_value());
  EXPECT_LT(*isp.lower_bound, isp.objective - 1);
  options.method = QuantizationMethod::kExact;
  const QuantizeResult exact = QuantizeOrDie(mesh, options);
  ASSERT_EQ(exact.termination, Termination::kOptimal);
  EXPECT_LE(*isp.lower_bound, exact.objective);
  EXPECT_LE(exact.objective, isp.objective + 1e-9);
}

// A row the result violates is not part of the problem it is certified for: it is left out
// rather than pushing the bound above the objective.
TEST(LowerBoundTest, RowsTheResultViolatesAreLeftOut) {
  const TMesh mesh =
      testing::LoadTMeshOrDie(testing::RealTMeshPath("hex-me/s07c_notch.tmesh.json"));
  QuantizeOptions options;
  options.scaling = mesh.levels()[4].scaling;
  options.lower_bound = LowerBoundMode::kNever;
  const QuantizeResult result = QuantizeOrDie(mesh, options);
  ASSERT_TRUE(result.valid);
  EXPECT_FALSE(result.lower_bound.has_value());
  const std::unique_ptr<MilpSolver> solver = NewCbcMilpSolver();
  const absl::StatusOr<double> plain = ComputeLowerBound(mesh, options, result.q, {}, *solver);
  ASSERT_TRUE(plain.ok());
  // q_0 >= (its value) + 1: a row over arc 0 alone that q violates.
  const SeparationRow violated{{{0, 1}}, result.q[0] + 1};
  const absl::StatusOr<double> with_row =
      ComputeLowerBound(mesh, options, result.q, {&violated, 1}, *solver);
  ASSERT_TRUE(with_row.ok());
  EXPECT_DOUBLE_EQ(*with_row, *plain);
  EXPECT_LE(*plain, result.objective);
}

TEST(LowerBoundTest, OptionsDecideWhetherIspResultsCarryOne) {
  const TMesh mesh = testing::LoadTMeshOrDie(
      testing::RealTMeshPath("singularity-constrained-fields/fanpart.tmesh.json"));
  QuantizeOptions options;
  options.scaling = mesh.levels()[2].scaling;
  options.lower_bound = LowerBoundMode::kAlways;
  EXPECT_TRUE(QuantizeOrDie(mesh, options).lower_bound.has_value());
  options.lower_bound = LowerBoundMode::kNever;
  const QuantizeResult without = QuantizeOrDie(mesh, options);
  EXPECT_FALSE(without.lower_bound.has_value());
  EXPECT_FALSE(without.gap.has_value());
  EXPECT_EQ(without.stats.lower_bound_seconds, 0);
}

// The relaxation of the whole model (every secant of every window) on CLP, and the lazy one, for
// the rows and windows of known bundle values x at `scaling`.
struct TwoRelaxations {
  double full = 0;
  std::optional<double> lazy;
};

TwoRelaxations SolveBothRelaxations(const TMesh& mesh, double scaling, std::span<const int64_t> q) {
  const ConsistencyMatrix consistency(mesh);
  const ArcBundles bundles(mesh, consistency);
  const BundleObjectives objectives(mesh, bundles, scaling);
  const QuantizationConstraints constraints(mesh, consistency, bundles, false);
  const std::vector<int64_t> x = constraints.BundleValues(q);
  const absl::StatusOr<QuantizationMilp> milp = BuildQuantizationMilp(objectives, constraints, x);
  EXPECT_TRUE(milp.ok()) << milp.status();
  const absl::StatusOr<LpResult> full = NewCbcMilpSolver()->SolveRelaxation(milp->model);
  EXPECT_TRUE(full.ok() && full->status == LpStatus::kOptimal);
  const std::vector<IntegerWindow> windows = ModelWindows(objectives, constraints, x);
  return {full->objective, SolveLazyEpigraphRelaxation(objectives, constraints, windows, x)};
}

// From the result of the same level the two secants around it nearly always suffice; from the
// result of another level (consistent, satisfying the simple rows, far from this level's optimum)
// the secants must follow the solution over several rounds. Both end at the full optimum.
TEST(LowerBoundTest, LazySecantsReachTheFullRelaxation) {
  for (const char* model : {"s09c_bridge", "s12c_cube_rounded_1", "n06u_anti_pentapyr"}) {
    const TMesh mesh = RealMesh(model);
    std::vector<std::vector<int64_t>> results;
    for (const Level& level : mesh.levels()) {
      QuantizeOptions options;
      options.scaling = level.scaling;
      options.lower_bound = LowerBoundMode::kNever;
      results.push_back(QuantizeOrDie(mesh, options).q);
    }
    for (size_t level = 0; level < results.size(); ++level) {
      const double scaling = mesh.levels()[level].scaling;
      for (size_t from : {level, results.size() - 1 - level}) {
        const TwoRelaxations bounds = SolveBothRelaxations(mesh, scaling, results[from]);
        ASSERT_TRUE(bounds.lazy.has_value()) << model << " level " << level << " from " << from;
        EXPECT_NEAR(*bounds.lazy, bounds.full, 1e-7 * (1 + std::abs(bounds.full)))
            << model << " level " << level << " from " << from;
      }
    }
  }
}

}  // namespace
}  // namespace ispq
