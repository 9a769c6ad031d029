// SPDX-License-Identifier: Apache-2.0
#include "core/exact/incumbent_checker.h"

#include <cstdint>
#include <vector>

#include "core/arc_bundles.h"
#include "core/consistency_matrix.h"
#include "core/exact/bundle_objective.h"
#include "core/exact/quantization_constraints.h"
#include "core/quantization_validator.h"
#include "core/separation_check.h"
#include "core/tmesh.h"
#include "gtest/gtest.h"
#include "tests/support/grid_tmesh_builder.h"
#include "tests/support/test_data.h"

namespace ispq {
namespace {

struct Problem {
  Problem(const testing::GridTMeshSpec& spec, double scaling)
      : grid(*testing::BuildGridTMesh(spec)),
        mesh(testing::TMeshOrDie(grid.proto())),
        consistency(mesh),
        bundles(mesh, consistency),
        objectives(mesh, bundles, scaling),
        constraints(mesh, consistency, bundles, false) {}
  // Whether the validator accepts x (per bundle) as a quantization.
  bool Valid(const std::vector<int64_t>& x) const {
    const absl::StatusOr<ValidationReport> report =
        ValidateQuantization(mesh, constraints.ArcValues(x));
    return report.ok() && report->valid();
  }
  testing::GridTMesh grid;
  TMesh mesh;
  ConsistencyMatrix consistency;
  ArcBundles bundles;
  BundleObjectives objectives;
  QuantizationConstraints constraints;
};

// One block with targets 2.3, 3.6 and 0.7 along u, v, w (bundles 0, 1, 2): rounding is optimal.
testing::GridTMeshSpec Box() {
  testing::GridTMeshSpec spec;
  spec.blocks = {{{0, 0, 0}, {1, 1, 1}}};
  spec.spacing = {std::vector<double>{2.3}, std::vector<double>{3.6}, std::vector<double>{0.7}};
  return spec;
}

// The verdicts on a box: the start is the first best and seen; a candidate breaking a simple row
// is not feasible; a worse or equal valid one is valid, a better one the new best.
TEST(IncumbentCheckerTest, JudgesCandidatesAgainstTheBestSoFar) {
  Problem p(Box(), 1.0);
  const std::vector<int64_t> start = {3, 4, 1};
  ASSERT_TRUE(p.Valid(start));
  IncumbentChecker checker(p.mesh, SeparationRule::kBothSearches, p.objectives, p.constraints,
                           start);
  EXPECT_EQ(std::vector<int64_t>(checker.best().begin(), checker.best().end()), start);
  EXPECT_DOUBLE_EQ(checker.best_objective(), p.objectives.Objective(start));
  EXPECT_EQ(checker.Check(start), CandidateVerdict::kSeen);

  EXPECT_EQ(checker.Check(std::vector<int64_t>{2, 4, 0}), CandidateVerdict::kNotFeasible);
  EXPECT_EQ(checker.checked(), 0);
  EXPECT_EQ(checker.Check(std::vector<int64_t>{2, 4, 0}), CandidateVerdict::kSeen);

  const std::vector<int64_t> worse = {3, 5, 1};
  ASSERT_TRUE(p.Valid(worse));
  EXPECT_EQ(checker.Check(worse), CandidateVerdict::kValid);
  EXPECT_EQ(checker.checked(), 1);
  EXPECT_EQ(std::vector<int64_t>(checker.best().begin(), checker.best().end()), start);

  const std::vector<int64_t> optimum = {2, 4, 1};
  ASSERT_TRUE(p.Valid(optimum));
  EXPECT_EQ(checker.Check(optimum), CandidateVerdict::kImproved);
  EXPECT_EQ(std::vector<int64_t>(checker.best().begin(), checker.best().end()), optimum);
  EXPECT_NEAR(checker.best_objective(), 4 * (0.09 + 0.16 + 0.09), 1e-12);
  EXPECT_EQ(checker.Check(optimum), CandidateVerdict::kSeen);
  EXPECT_EQ(checker.checked(), 2);
  EXPECT_EQ(checker.rows_added(), 0);
}

// An equally good valid candidate keeps the earlier best (ISP's result unless beaten).
TEST(IncumbentCheckerTest, ATieKeepsTheEarlierBest) {
  testing::GridTMeshSpec spec = Box();
  spec.spacing[0] = {2.5};  // u = 2 and u = 3 are equally good
  Problem p(spec, 1.0);
  IncumbentChecker checker(p.mesh, SeparationRule::kBothSearches, p.objectives, p.constraints,
                           {3, 4, 1});
  EXPECT_EQ(checker.Check(std::vector<int64_t>{2, 4, 1}), CandidateVerdict::kValid);
  EXPECT_EQ(checker.best()[0], 3);
}

// T6 with the bottom layer flat: the consistency and simple rows hold, the separation check finds
// the feature node touching the bottom, and its row joins the constraints so the candidate no
// longer satisfies them.
TEST(IncumbentCheckerTest, ACandidateTheSearchRejectsAddsItsRows) {
  testing::GridTMeshSpec spec;
  for (int w : {1, 0}) {
    for (int v = 0; v < 2; ++v) {
      for (int u = 0; u < 2; ++u) spec.blocks.push_back({{u, v, w}, {u + 1, v + 1, w + 1}});
    }
  }
  spec.feature_nodes = {{1, 1, 1}};
  Problem p(spec, 1.0);
  const std::vector<int64_t> ones(p.bundles.num_bundles(), 1);
  ASSERT_TRUE(p.Valid(ones));
  IncumbentChecker checker(p.mesh, SeparationRule::kBothSearches, p.objectives, p.constraints,
                           ones);
  std::vector<int64_t> flat = ones;
  flat[p.bundles.bundle_of(p.grid.ArcBetween({1, 1, 0}, {1, 1, 1}))] = 0;
  ASSERT_TRUE(p.constraints.SatisfiesFixedRows(flat));
  EXPECT_EQ(checker.Check(flat), CandidateVerdict::kSeparated);
  EXPECT_EQ(checker.rows_added(), 1);
  EXPECT_EQ(p.constraints.num_separation_rows(), 1);
  EXPECT_FALSE(p.constraints.SatisfiedBy(flat));
  EXPECT_TRUE(p.constraints.SatisfiedBy(ones));
  EXPECT_EQ(std::vector<int64_t>(checker.best().begin(), checker.best().end()), ones);
  EXPECT_EQ(checker.Check(flat), CandidateVerdict::kSeen);
}

}  // namespace
}  // namespace ispq
