// SPDX-License-Identifier: Apache-2.0
// The exact model (core/exact/quantization_milp.h) solved by the CBC back end
// (core/exact/cbc_milp_solver.h) on grid meshes whose optima are known by hand or by brute force:
// optima, relaxations, windows, initial solutions, cutoffs and the callbacks.
#include "core/exact/quantization_milp.h"

#include <cmath>
#include <limits>
#include <memory>
#include <vector>

#include "core/arc_bundles.h"
#include "core/consistency_matrix.h"
#include "core/exact/bundle_objective.h"
#include "core/exact/cbc_milp_solver.h"
#include "core/exact/quantization_constraints.h"
#include "gtest/gtest.h"
#include "tests/support/enumerated_optimum.h"
#include "tests/support/grid_tmesh_builder.h"
#include "tests/support/test_data.h"

namespace ispq {
namespace {

// The mesh with its bundles, objective and constraints (no separation rows).
struct Problem {
  explicit Problem(const testing::GridTMeshSpec& spec, double scaling)
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

testing::GridTMeshSpec Box() {
  testing::GridTMeshSpec spec;
  spec.blocks = {{{0, 0, 0}, {1, 1, 1}}};
  spec.spacing = {std::vector<double>{2.3}, std::vector<double>{3.6}, std::vector<double>{0.7}};
  return spec;
}

// Two half-width blocks on a full-width one: the lower width is the sum of the upper ones.
testing::GridTMeshSpec TJunction() {
  testing::GridLayout2D layout;
  layout.blocks = {{{0, 0}, {2, 1}}, {{0, 1}, {1, 2}}, {{1, 1}, {2, 2}}};
  layout.spacing = {std::vector<double>{1.4, 1.4}, std::vector<double>{1.0, 1.0}};
  return testing::ExtrudeLayout(layout);
}

// Records what the solver reports; stops at the first incumbent if asked.
class Recorder : public MilpCallbacks {
 public:
  bool OnIncumbent(std::span<const double>, double objective) override {
    incumbents.push_back(objective);
    return !stop_at_incumbent;
  }
  bool OnProgress(double, int64_t) override { return true; }
  bool stop_at_incumbent = false;
  std::vector<double> incumbents;
};

// Rounding each axis of a box is optimal: q = (2, 4, 1), d = 4 (0.09 + 0.16 + 0.09). The LP
// relaxation is integral here, so it meets the optimum.
TEST(QuantizationMilpTest, BoxOptimumIsTheRoundedTargets) {
  const Problem p(Box(), 1.0);
  const std::vector<int64_t> start = {3, 3, 2};  // a worse feasible q windows the model
  const absl::StatusOr<QuantizationMilp> milp =
      BuildQuantizationMilp(p.objectives, p.constraints, p.objectives.Objective(start));
  ASSERT_TRUE(milp.ok()) << milp.status();
  const std::unique_ptr<MilpSolver> solver = NewCbcMilpSolver();
  Recorder recorder;
  const absl::StatusOr<MilpResult> result = solver->Solve(milp->model, {}, recorder);
  ASSERT_TRUE(result.ok()) << result.status();
  ASSERT_EQ(result->status, MilpStatus::kOptimal);
  ASSERT_TRUE(result->best.has_value());
  EXPECT_EQ(milp->BundleValuesOf(*result->best), (std::vector<int64_t>{2, 4, 1}));
  EXPECT_NEAR(result->best_objective, 4 * (0.09 + 0.16 + 0.09), 1e-7);
  EXPECT_NEAR(result->bound, result->best_objective, 1e-6);
  const absl::StatusOr<LpResult> relaxation = solver->SolveRelaxation(milp->model);
  ASSERT_TRUE(relaxation.ok());
  ASSERT_EQ(relaxation->status, LpStatus::kOptimal);
  EXPECT_NEAR(relaxation->objective, result->best_objective, 1e-7);
}

// On a T-junction the optimum is the brute-force one (every consistent q near the targets, the
// first the validator accepts), at scalings where rounding arc by arc is inconsistent.
TEST(QuantizationMilpTest, TJunctionOptimumEqualsTheEnumeratedOne) {
  for (double scaling : {1.0, 1.3, 2.2, 3.7}) {
    const Problem p(TJunction(), scaling);
    const absl::StatusOr<testing::EnumeratedOptimum> optimum =
        testing::EnumerateOptimum(p.mesh, scaling, 1);
    ASSERT_TRUE(optimum.ok()) << optimum.status();
    const std::vector<int64_t> x = p.constraints.BundleValues(optimum->q);
    const absl::StatusOr<QuantizationMilp> milp =
        BuildQuantizationMilp(p.objectives, p.constraints, optimum->objective + 3);
    ASSERT_TRUE(milp.ok());
    Recorder recorder;
    const absl::StatusOr<MilpResult> result = NewCbcMilpSolver()->Solve(milp->model, {}, recorder);
    ASSERT_TRUE(result.ok());
    ASSERT_EQ(result->status, MilpStatus::kOptimal) << scaling;
    EXPECT_NEAR(result->best_objective, optimum->objective, 1e-6) << scaling;
    EXPECT_NEAR(p.objectives.Objective(milp->BundleValuesOf(*result->best)), optimum->objective,
                1e-6);
    EXPECT_TRUE(p.constraints.SatisfiedBy(x));
  }
}

// Given the optimum as its initial solution, CBC proves it; with a cutoff below the optimum
// there is nothing to find; a callback that says stop stops the search.
TEST(QuantizationMilpTest, InitialSolutionCutoffAndStop) {
  const double scaling = 2.2;
  const Problem p(TJunction(), scaling);
  const absl::StatusOr<testing::EnumeratedOptimum> optimum =
      testing::EnumerateOptimum(p.mesh, scaling, 1);
  ASSERT_TRUE(optimum.ok());
  const std::vector<int64_t> x = p.constraints.BundleValues(optimum->q);
  const absl::StatusOr<QuantizationMilp> milp =
      BuildQuantizationMilp(p.objectives, p.constraints, optimum->objective + 5);
  ASSERT_TRUE(milp.ok());
  const std::unique_ptr<MilpSolver> solver = NewCbcMilpSolver();

  MilpSolveOptions warm;
  warm.initial_solution = milp->ColumnsOf(p.objectives, x);
  ASSERT_TRUE(warm.initial_solution.has_value());
  Recorder quiet;
  absl::StatusOr<MilpResult> result = solver->Solve(milp->model, warm, quiet);
  ASSERT_TRUE(result.ok());
  EXPECT_EQ(result->status, MilpStatus::kOptimal);
  EXPECT_NEAR(result->best_objective, optimum->objective, 1e-6);

  MilpSolveOptions below;
  below.cutoff = optimum->objective - 1e-3;
  result = solver->Solve(milp->model, below, quiet);
  ASSERT_TRUE(result.ok());
  EXPECT_EQ(result->status, MilpStatus::kInfeasible);
  EXPECT_FALSE(result->best.has_value());
  EXPECT_DOUBLE_EQ(result->bound, below.cutoff);

  Recorder stopper;
  stopper.stop_at_incumbent = true;
  result = solver->Solve(milp->model, {}, stopper);
  ASSERT_TRUE(result.ok());
  ASSERT_FALSE(stopper.incumbents.empty());
  if (result->status == MilpStatus::kStopped) {
    EXPECT_LE(result->bound, optimum->objective + 1e-6);
  }
}

// Columns of bundle values inside the windows carry z = f(x); outside a window there are none.
TEST(QuantizationMilpTest, ColumnsOfBundleValuesAndWindows) {
  const Problem p(Box(), 1.0);
  const std::vector<int64_t> optimum = {2, 4, 1};
  const double objective = p.objectives.Objective(optimum);
  const absl::StatusOr<QuantizationMilp> milp =
      BuildQuantizationMilp(p.objectives, p.constraints, objective + 8);
  ASSERT_TRUE(milp.ok());
  const std::optional<std::vector<double>> columns = milp->ColumnsOf(p.objectives, optimum);
  ASSERT_TRUE(columns.has_value());
  EXPECT_EQ(milp->BundleValuesOf(*columns), optimum);
  double value = milp->model.objective_offset;
  for (int j = 0; j < milp->model.num_columns(); ++j) {
    value += milp->model.objective[j] * (*columns)[j];
  }
  EXPECT_NEAR(value, objective, 1e-9);
  EXPECT_FALSE(milp->ColumnsOf(p.objectives, std::vector<int64_t>{2, 40, 1}).has_value());
  // A bound so far above the minimum that the windows would be enormous is refused.
  EXPECT_EQ(BuildQuantizationMilp(p.objectives, p.constraints, 1e18).status().code(),
            absl::StatusCode::kResourceExhausted);
}

// Without rows a feasibility model is feasible; a contradictory pair of rows makes it not.
TEST(QuantizationMilpTest, FeasibilityModelDetectsContradictoryRows) {
  Problem p(Box(), 1.0);
  const std::unique_ptr<MilpSolver> solver = NewCbcMilpSolver();
  absl::StatusOr<LpResult> lp =
      solver->SolveRelaxation(BuildFeasibilityModel(p.bundles.num_bundles(), p.constraints));
  ASSERT_TRUE(lp.ok());
  EXPECT_EQ(lp->status, LpStatus::kOptimal);
  // u-extent <= -1 contradicts the block-extent row u-extent >= 0.
  const ArcId u_arc = p.bundles.arcs(0)[0];
  SeparationRow impossible{{{u_arc, -1}}, 1};
  ASSERT_TRUE(p.constraints.AddSeparationRow(impossible, std::nullopt));
  EXPECT_FALSE(p.constraints.AddSeparationRow(impossible, std::nullopt));  // deduplicated
  lp = solver->SolveRelaxation(BuildFeasibilityModel(p.bundles.num_bundles(), p.constraints));
  ASSERT_TRUE(lp.ok());
  EXPECT_EQ(lp->status, LpStatus::kInfeasible);
  // Its failsafe twin (here x_u >= 1) stands in when asked.
  Problem q(Box(), 1.0);
  ASSERT_TRUE(q.constraints.AddSeparationRow(impossible, SeparationRow{{{u_arc, 1}}, 1}));
  const int last = q.constraints.num_inequalities() - 1;
  EXPECT_EQ(q.constraints.inequality(last)[0].coef, -1);
  q.constraints.UseFailsafeForms();
  ASSERT_EQ(q.constraints.inequality(last).size(), 1u);
  EXPECT_EQ(q.constraints.inequality(last)[0].var, 0);
  EXPECT_EQ(q.constraints.inequality(last)[0].coef, 1);
  EXPECT_EQ(q.constraints.rhs(last), 1);
  EXPECT_TRUE(q.constraints.SatisfiedBy(std::vector<int64_t>{2, 4, 1}));
}

}  // namespace
}  // namespace ispq
