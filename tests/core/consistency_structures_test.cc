// SPDX-License-Identifier: Apache-2.0
// Consistency matrix, bundles, subproblems and hex count on meshes with known answers.
#include "core/arc_bundles.h"
#include "core/block_extents.h"
#include "core/consistency_matrix.h"
#include "core/mesh_stats.h"
#include "core/resolution_levels.h"
#include "core/subproblems.h"
#include "gtest/gtest.h"
#include "tests/support/test_data.h"

namespace ispq {
namespace {

TEST(ConsistencyStructuresTest, SingleCube) {
  const TMesh cube = testing::LoadTMeshOrDie(testing::RealTMeshPath("hex-me/s01c_cube.tmesh.json"));
  const ConsistencyMatrix consistency(cube);
  EXPECT_EQ(consistency.num_rows(), 12);  // 6 patches x 2 axes
  const ArcBundles bundles(cube, consistency);
  EXPECT_EQ(bundles.num_bundles(), 3);  // the 4 parallel edges of each axis
  for (BundleId b = 0; b < 3; ++b) EXPECT_EQ(bundles.arcs(b).size(), 4u);
  const Subproblems subproblems(cube, consistency, bundles);
  EXPECT_EQ(subproblems.num_subproblems(), 3);

  // q = extents (2, 3, 4) along the bundles' axes: consistent, 24 hexes.
  std::vector<int64_t> q(cube.num_arcs());
  std::array<int64_t, 3> extent_of_axis = {2, 3, 4};
  for (ArcId a = 0; a < cube.num_arcs(); ++a) {
    q[a] = extent_of_axis[AxisOf(*cube.HalfarcDirInBlock(HalfarcOf(a, false), 0))];
  }
  for (int r = 0; r < consistency.num_rows(); ++r) EXPECT_EQ(consistency.RowValue(r, q), 0);
  EXPECT_EQ(HexCount(cube, q), std::optional<int64_t>(24));
  for (int axis = 0; axis < 3; ++axis)
    EXPECT_EQ(BlockExtent(cube, 0, axis, q), extent_of_axis[axis]);

  // Changing one arc breaks exactly the two rows of the patches containing it... and no others.
  q[0] += 1;
  int violated = 0;
  for (int r = 0; r < consistency.num_rows(); ++r) violated += consistency.RowValue(r, q) != 0;
  EXPECT_EQ(violated, 2);
}

TEST(ConsistencyStructuresTest, BundlingMergesTerms) {
  const TMesh prism =
      testing::LoadTMeshOrDie(testing::RealTMeshPath("hex-me/s02c_prism.tmesh.json"));
  const ConsistencyMatrix consistency(prism);
  const ArcBundles bundles(prism, consistency);
  // A row whose two sides are one arc each vanishes once both arcs share a bundle.
  for (int r = 0; r < consistency.num_rows(); ++r) {
    if (consistency.row(r).size() == 2) {
      EXPECT_TRUE(bundles.ToBundleTerms(consistency.row(r)).empty());
    }
  }
  EXPECT_LT(bundles.num_bundles(), prism.num_arcs());
}

TEST(ResolutionLevelsTest, MatchesTheFormatDefinition) {
  const std::vector<double> lengths = {4.0, 1.0, 2.0, 8.0};
  EXPECT_DOUBLE_EQ(*ScalingForPercent(lengths, 0), 0.5 / 1.0);
  EXPECT_DOUBLE_EQ(*ScalingForPercent(lengths, 25), 0.5 / 2.0);  // k = 1
  EXPECT_DOUBLE_EQ(*ScalingForPercent(lengths, 50), 0.5 / 4.0);  // k = 2
  EXPECT_DOUBLE_EQ(*ScalingForPercent(lengths, 100), 0.999 * 0.5 / 8.0);
  EXPECT_DOUBLE_EQ(*ScalingForPercent(lengths, 10), 0.5 / 1.0);  // round(0.4) = 0
  EXPECT_DOUBLE_EQ(*ScalingForPercent(lengths, 63), 0.5 / 8.0);  // round(2.52) = 3
  EXPECT_FALSE(ScalingForPercent({}, 5).has_value());
  EXPECT_FALSE(ScalingForPercent(lengths, 101).has_value());
}

TEST(MeshStatsTest, CubeCounts) {
  const MeshStats s = ComputeMeshStats(
      testing::LoadTMeshOrDie(testing::RealTMeshPath("hex-me/s01c_cube.tmesh.json")));
  EXPECT_EQ(s.blocks, 1);
  EXPECT_EQ(s.patches, 6);
  EXPECT_EQ(s.arcs, 12);
  EXPECT_EQ(s.nodes, 8);
  EXPECT_EQ(s.critical_entities, 26);
  EXPECT_EQ(s.critical_links, 12);
  EXPECT_EQ(s.critical_regions, 6);
  EXPECT_EQ(s.bundles, 3);
  EXPECT_EQ(s.subproblems, 3);
}

}  // namespace
}  // namespace ispq
