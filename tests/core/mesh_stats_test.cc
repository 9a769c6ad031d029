// SPDX-License-Identifier: Apache-2.0
#include "core/mesh_stats.h"

#include "gtest/gtest.h"
#include "tests/support/test_data.h"

namespace ispq {
namespace {

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
