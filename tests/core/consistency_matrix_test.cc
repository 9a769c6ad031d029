// SPDX-License-Identifier: Apache-2.0
// The consistency rows (paper eq. 1b) on a mesh with known answers.
#include "core/consistency_matrix.h"

#include <array>
#include <optional>
#include <vector>

#include "core/block_extents.h"
#include "gtest/gtest.h"
#include "tests/support/test_data.h"

namespace ispq {
namespace {

TEST(ConsistencyMatrixTest, TwoRowsPerPatchHoldForConsistentExtents) {
  const TMesh cube = testing::LoadTMeshOrDie(testing::RealTMeshPath("hex-me/s01c_cube.tmesh.json"));
  const ConsistencyMatrix consistency(cube);
  EXPECT_EQ(consistency.num_rows(), 12);  // 6 patches x 2 axes

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

}  // namespace
}  // namespace ispq
