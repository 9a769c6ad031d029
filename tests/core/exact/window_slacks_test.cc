// SPDX-License-Identifier: Apache-2.0
// The slack of each bundle's window (core/exact/window_slacks.h): per independent component where
// the known q satisfies the component's rows, the global slack elsewhere.
#include "core/exact/window_slacks.h"

#include <vector>

#include "core/arc_bundles.h"
#include "core/consistency_matrix.h"
#include "gtest/gtest.h"
#include "tests/support/grid_tmesh_builder.h"
#include "tests/support/test_data.h"

namespace ispq {
namespace {

// Two boxes apart from each other: two independent components of three bundles each.
TMesh TwoBoxes() {
  testing::GridTMeshSpec spec;
  spec.blocks = {{{0, 0, 0}, {1, 1, 1}}, {{2, 0, 0}, {3, 1, 1}}};
  spec.spacing = {std::vector<double>{2.3, 1.0, 4.2}, std::vector<double>{3.6},
                  std::vector<double>{0.7}};
  absl::StatusOr<testing::GridTMesh> grid = testing::BuildGridTMesh(spec);
  EXPECT_TRUE(grid.ok()) << grid.status();
  return testing::TMeshOrDie(grid->proto());
}

TEST(WindowSlacksTest, PerComponentWhereTheKnownQSatisfiesItsRows) {
  const TMesh mesh = TwoBoxes();
  const ConsistencyMatrix consistency(mesh);
  const ArcBundles bundles(mesh, consistency);
  ASSERT_EQ(bundles.num_bundles(), 6);
  const BundleObjectives objectives(mesh, bundles, 1.0);
  QuantizationConstraints constraints(mesh, consistency, bundles, false);
  // Each box one away from its best integers on one axis.
  std::vector<int64_t> x(6);
  for (BundleId b = 0; b < 6; ++b) x[b] = objectives.BestInteger(b);
  const BundleId first = 0;
  const BundleId other = bundles.bundle_of(mesh.num_arcs() - 1);
  x[first] += 1;
  x[other] += 1;
  const double first_excess =
      objectives.Value(first, x[first]) - objectives.Value(first, objectives.BestInteger(first));
  const double other_excess =
      objectives.Value(other, x[other]) - objectives.Value(other, objectives.BestInteger(other));
  const std::vector<double> slacks = WindowSlacks(objectives, constraints, x);
  ASSERT_NE(first_excess, other_excess);
  int in_first = 0, in_other = 0;
  for (BundleId b = 0; b < 6; ++b) {
    in_first += slacks[b] == first_excess;
    in_other += slacks[b] == other_excess;
  }
  EXPECT_EQ(in_first, 3);  // each box's three bundles share its own slack
  EXPECT_EQ(in_other, 3);
  EXPECT_DOUBLE_EQ(slacks[first], first_excess);
  EXPECT_DOUBLE_EQ(slacks[other], other_excess);

  // A row of the first box that x violates: that box only knows the global bound now.
  SeparationRow violated{{{bundles.arcs(first)[0], 1}}, x[first] + 1};
  ASSERT_TRUE(constraints.AddSeparationRow(violated, std::nullopt));
  const std::vector<double> after = WindowSlacks(objectives, constraints, x);
  EXPECT_DOUBLE_EQ(after[first], first_excess + other_excess);
  EXPECT_DOUBLE_EQ(after[other], other_excess);
}

}  // namespace
}  // namespace ispq
