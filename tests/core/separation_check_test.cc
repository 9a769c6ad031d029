// SPDX-License-Identifier: Apache-2.0
#include "core/separation_check.h"

#include <array>
#include <cstdint>
#include <utility>
#include <vector>

#include "absl/status/statusor.h"
#include "core/quantization_validator.h"
#include "core/rotation.h"
#include "core/separation_search.h"
#include "core/tmesh.h"
#include "gtest/gtest.h"
#include "tests/support/grid_tmesh_builder.h"
#include "tests/support/test_data.h"

namespace ispq {
namespace {

using ::ispq::testing::BuildGridTMesh;
using ::ispq::testing::GridTMesh;
using ::ispq::testing::GridTMeshSpec;

struct Example {
  GridTMesh grid;
  TMesh mesh;
};

// T6: a 2x2x2 grid of unit blocks whose centre is a feature node, top layer first (so the
// centre's search starts in it); with `turn_bottom_layer`, T10: the bottom layer's frames turned
// by 90 degrees about w, so that the reference search (unsorted block boxes) no longer enters
// them from the centre.
Example FeatureCentre(bool turn_bottom_layer) {
  GridTMeshSpec spec;
  for (int w : {1, 0}) {
    for (int v = 0; v < 2; ++v) {
      for (int u = 0; u < 2; ++u) spec.blocks.push_back({{u, v, w}, {u + 1, v + 1, w + 1}});
    }
  }
  spec.feature_nodes = {{1, 1, 1}};
  if (turn_bottom_layer) {
    const int quarter_turn = Rotation::FromSignedPermutation({-2, 1, 3})->index();
    for (int b = 4; b < 8; ++b) spec.block_rotations.push_back({b, quarter_turn});
  }
  absl::StatusOr<GridTMesh> grid = BuildGridTMesh(spec);
  EXPECT_TRUE(grid.ok()) << grid.status();
  TMesh mesh = testing::TMeshOrDie(grid->proto());
  return {*std::move(grid), std::move(mesh)};
}

// q with every w arc of the bottom layer `bottom_height` long and every other arc 1, checked
// consistent by the validator.
std::vector<int64_t> LayerQ(const Example& example, int64_t bottom_height) {
  std::vector<int64_t> q;
  for (ArcId a = 0; a < example.mesh.num_arcs(); ++a) {
    const auto& [from, to] = example.grid.arc_ends(a);
    q.push_back(from[2] != to[2] && from[2] == 0 ? bottom_height : 1);
  }
  const absl::StatusOr<ValidationReport> report = ValidateQuantization(example.mesh, q);
  EXPECT_TRUE(report.ok() && report->consistent());
  return q;
}

// With the bottom layer flat, both searches find the centre touching the bottom. The product's
// first answer is the reference search's alone; all violations are the reference's then the
// sorted search's.
TEST(SeparationCheckTest, TheReferenceSearchAnswersFirstAndBothAnswerAll) {
  const Example example = FeatureCentre(false);
  const std::vector<int64_t> flat = LayerQ(example, 0);
  SeparationCheck both(example.mesh, SeparationRule::kBothSearches);
  EXPECT_EQ(&both.mesh(), &example.mesh);
  EXPECT_EQ(both.rule(), SeparationRule::kBothSearches);
  const std::vector<SeparationViolation> first = both.FindFirstViolations(flat);
  ASSERT_EQ(first.size(), 1u);
  EXPECT_EQ(first[0].found_by, BlockBoxMode::kReferenceUnsorted);
  EXPECT_EQ(first[0].start_node, example.grid.NodeAt({1, 1, 1}));
  const std::vector<SeparationViolation> all = both.FindAllViolations(flat);
  ASSERT_EQ(all.size(), 2u);
  EXPECT_EQ(all[0].found_by, BlockBoxMode::kReferenceUnsorted);
  EXPECT_EQ(all[1].found_by, BlockBoxMode::kSorted);
  EXPECT_EQ(all[1].default_row, all[0].default_row);

  SeparationCheck reference(example.mesh, SeparationRule::kReferenceSearch);
  EXPECT_EQ(reference.rule(), SeparationRule::kReferenceSearch);
  const std::vector<SeparationViolation> reference_all = reference.FindAllViolations(flat);
  ASSERT_EQ(reference_all.size(), 1u);
  EXPECT_EQ(reference_all[0].found_by, BlockBoxMode::kReferenceUnsorted);
}

// T10: the reference search misses the row behind the sign-flipping transition. The product's
// rule still finds it with the sorted search; upstream's rule alone calls q separating.
TEST(SeparationCheckTest, TheSortedSearchFindsWhatTheReferenceMisses) {
  const Example example = FeatureCentre(true);
  ASSERT_LT(example.mesh.node_blocks(example.grid.NodeAt({1, 1, 1}))[0], 4);
  const std::vector<int64_t> flat = LayerQ(example, 0);
  SeparationCheck both(example.mesh, SeparationRule::kBothSearches);
  const std::vector<SeparationViolation> first = both.FindFirstViolations(flat);
  ASSERT_EQ(first.size(), 1u);
  EXPECT_EQ(first[0].found_by, BlockBoxMode::kSorted);
  const std::vector<SeparationViolation> all = both.FindAllViolations(flat);
  ASSERT_EQ(all.size(), 1u);
  EXPECT_EQ(all[0].found_by, BlockBoxMode::kSorted);

  SeparationCheck reference(example.mesh, SeparationRule::kReferenceSearch);
  EXPECT_TRUE(reference.FindFirstViolations(flat).empty());
  EXPECT_TRUE(reference.FindAllViolations(flat).empty());
}

// The remembered clean q answers only for itself: a different q of the same size is searched,
// and a q whose first search found violations is never remembered as clean.
TEST(SeparationCheckTest, OnlyTheLastCleanQIsAnsweredWithoutSearching) {
  const Example example = FeatureCentre(false);
  const std::vector<int64_t> regular = LayerQ(example, 1);
  const std::vector<int64_t> flat = LayerQ(example, 0);
  const std::vector<int64_t> tall = LayerQ(example, 2);
  SeparationCheck check(example.mesh, SeparationRule::kBothSearches);
  EXPECT_TRUE(check.FindFirstViolations(regular).empty());
  EXPECT_TRUE(check.FindAllViolations(regular).empty());
  EXPECT_EQ(check.FindAllViolations(flat).size(), 2u);
  EXPECT_EQ(check.FindFirstViolations(flat).size(), 1u);
  EXPECT_EQ(check.FindAllViolations(flat).size(), 2u);
  EXPECT_TRUE(check.FindAllViolations(regular).empty());  // still the last clean q
  EXPECT_TRUE(check.FindFirstViolations(tall).empty());
  EXPECT_TRUE(check.FindAllViolations(tall).empty());
  EXPECT_EQ(check.FindAllViolations(flat).size(), 2u);
}

// The sink form hands over what the vector form returns and stops the search when told to.
TEST(SeparationCheckTest, TheSinkReceivesTheFirstViolationsAndCanStopTheSearch) {
  const TMesh cube = testing::LoadTMeshOrDie(testing::RealTMeshPath("hex-me/s01c_cube.tmesh.json"));
  // Every arc along u collapsed: 16 violations (core/README.md, case T4).
  std::vector<int64_t> q(cube.num_arcs(), 1);
  for (int edge = 0; edge < 4; ++edge) {
    for (ArcId a : cube.block_edge_arcs(0, edge)) q[a] = 0;
  }
  SeparationCheck check(cube, SeparationRule::kBothSearches);
  const std::vector<SeparationViolation> expected = check.FindFirstViolations(q);
  ASSERT_EQ(expected.size(), 16u);
  std::vector<SeparationRow> rows;
  EXPECT_EQ(check.FindFirstViolations(q,
                                      [&](SeparationViolation& v) {
                                        rows.push_back(v.default_row);
                                        return true;
                                      }),
            16);
  ASSERT_EQ(rows.size(), expected.size());
  for (size_t i = 0; i < rows.size(); ++i) EXPECT_EQ(rows[i], expected[i].default_row);
  int calls = 0;
  EXPECT_EQ(check.FindFirstViolations(q, [&](SeparationViolation&) { return ++calls < 3; }), 3);
  EXPECT_EQ(calls, 3);
  // A stopped search is no verdict of cleanliness.
  EXPECT_EQ(check.FindAllViolations(q).size(), 32u);
}

}  // namespace
}  // namespace ispq
