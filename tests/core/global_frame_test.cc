// SPDX-License-Identifier: Apache-2.0
// One frame for a whole part (core/global_frame.h): the grid's own coordinates on grid parts,
// none around a singular arc, and coordinates only for a q without a handle's period.
#include "core/global_frame.h"

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/bundle_potentials.h"
#include "gtest/gtest.h"
#include "tests/support/grid_tmesh_builder.h"
#include "tests/support/test_data.h"

namespace ispq {
namespace {

using testing::GridBox;
using testing::GridTMesh;
using testing::GridTMeshSpec;

// Sums of the first k intervals of each axis.
IntVec3 SumOfIntervals(const std::array<std::vector<int64_t>, 3>& intervals,
                       const testing::GridPoint& at) {
  IntVec3 point{};
  for (int axis = 0; axis < 3; ++axis) {
    for (int k = 0; k < at[axis]; ++k) point[axis] += intervals[axis][k];
  }
  return point;
}

// An L of blocks with a T-junction: every node's coordinates are its grid point's, up to the
// origin, whatever the q (negative intervals included).
TEST(GlobalFrameTest, GridPartsHaveTheirGridCoordinates) {
  GridTMeshSpec spec;
  spec.blocks = {GridBox{{0, 0, 0}, {1, 1, 1}}, GridBox{{1, 0, 0}, {2, 1, 1}},
                 GridBox{{0, 1, 0}, {2, 2, 1}}, GridBox{{0, 0, 1}, {1, 2, 2}}};
  const GridTMesh grid = testing::BuildGridTMeshOrDie(spec);
  const TMesh mesh = testing::TMeshOrDie(grid.proto());
  const std::optional<GlobalFrame> frame = GlobalFrame::Compute(mesh);
  ASSERT_TRUE(frame.has_value());
  const std::array<std::vector<int64_t>, 3> intervals = {{{3, -1}, {2, 5}, {1, 4}}};
  std::vector<IntVec3> coordinates;
  ASSERT_TRUE(frame->NodeCoordinates(mesh, grid.QFromIntervals(intervals), coordinates));
  const NodeId corner = grid.NodeAt({0, 0, 0});
  ASSERT_NE(corner, kNoId);
  for (NodeId n = 0; n < mesh.num_nodes(); ++n) {
    EXPECT_EQ(Subtract(coordinates[n], coordinates[corner]),
              SumOfIntervals(intervals, grid.node_point(n)))
        << "node " << n;
  }
}

// A ring of eight blocks around a hole has one frame, but the two sides of the hole may differ
// in length: such a q is no difference of coordinates.
TEST(GlobalFrameTest, AHandlesPeriodLeavesNoCoordinates) {
  GridTMeshSpec spec = testing::RingAroundAHole();
  const GridTMesh grid = testing::BuildGridTMeshOrDie(spec);
  const TMesh mesh = testing::TMeshOrDie(grid.proto());
  const std::optional<GlobalFrame> frame = GlobalFrame::Compute(mesh);
  ASSERT_TRUE(frame.has_value());
  std::vector<int64_t> q = grid.QFromIntervals({{{1, 1, 1}, {1, 1, 1}, {1}}});
  std::vector<IntVec3> coordinates;
  EXPECT_TRUE(frame->NodeCoordinates(mesh, q, coordinates));
  // The left column's middle block twice as long along v: still consistent (no patch joins its
  // v edges to the right column's), but the hole's two sides now differ.
  int lengthened = 0;
  for (ArcId a = 0; a < mesh.num_arcs(); ++a) {
    const auto& [from, to] = grid.arc_ends(a);
    if (from[0] == to[0] && from[0] <= 1 && from[1] == 1 && to[1] == 2) {
      q[a] = 2;
      ++lengthened;
    }
  }
  ASSERT_EQ(lengthened, 4);
  EXPECT_FALSE(frame->NodeCoordinates(mesh, q, coordinates));
}

// Real meshes: a frame exactly where the patches' rotations join every block's axes into three
// global ones (core/bundle_potentials.h's GlobalBlockDirections; every real part is connected).
TEST(GlobalFrameTest, RealMeshesHaveOneWhereTheirFramesAreGlobal) {
  int with = 0, without = 0;
  for (const std::string& file : testing::RealTMeshFiles()) {
    SCOPED_TRACE(testing::ShortName(file));
    const TMesh mesh = testing::LoadTMeshOrDie(file);
    const bool global = GlobalBlockDirections(mesh).has_value();
    EXPECT_EQ(GlobalFrame::Compute(mesh).has_value(), global);
    (global ? with : without) += 1;
  }
  EXPECT_GT(with, 0);
  EXPECT_GT(without, 0);
}

}  // namespace
}  // namespace ispq
