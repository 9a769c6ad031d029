// SPDX-License-Identifier: Apache-2.0
#include "core/halfarc_neighborhood.h"

#include <algorithm>
#include <utility>
#include <vector>

#include "absl/status/statusor.h"
#include "core/tmesh.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "tests/support/grid_tmesh_builder.h"
#include "tests/support/test_data.h"

namespace ispq {
namespace {

using ::ispq::testing::BuildGridTMesh;
using ::ispq::testing::GridTMesh;
using ::ispq::testing::GridTMeshSpec;
using ::testing::UnorderedElementsAreArray;

struct Example {
  GridTMesh grid;
  TMesh mesh;
};

Example Build(const GridTMeshSpec& spec) {
  absl::StatusOr<GridTMesh> grid = BuildGridTMesh(spec);
  EXPECT_TRUE(grid.ok()) << grid.status();
  TMesh mesh = testing::TMeshOrDie(grid->proto());
  return {*std::move(grid), std::move(mesh)};
}

GridTMeshSpec Grid2x2x2() {
  GridTMeshSpec spec;
  for (int w = 0; w < 2; ++w) {
    for (int v = 0; v < 2; ++v) {
      for (int u = 0; u < 2; ++u) spec.blocks.push_back({{u, v, w}, {u + 1, v + 1, w + 1}});
    }
  }
  return spec;
}

// A block next to a taller one: T-junctions give patches with more than four halfarcs.
GridTMeshSpec Step() {
  GridTMeshSpec spec;
  spec.blocks = {{{0, 0, 0}, {1, 1, 2}}, {{1, 0, 0}, {2, 1, 1}}};
  return spec;
}

// The interior arc at the centre of a 2x2x2 grid: four walls around it, four blocks.
TEST(HalfarcNeighborhoodTest, AnInteriorArcHasFourHalfpatchesAndFourBlocks) {
  const Example example = Build(Grid2x2x2());
  const ArcId a = example.grid.ArcBetween({1, 1, 0}, {1, 1, 1});
  ASSERT_GE(a, 0);
  for (bool reversed : {false, true}) {
    const HalfarcId h = HalfarcOf(a, reversed);
    const std::vector<HalfpatchId> around = HalfpatchesAroundHalfarc(example.mesh, h);
    ASSERT_EQ(around.size(), 4u);
    for (HalfpatchId hp : around) {
      EXPECT_GE(IndexInHalfpatchCycle(example.mesh, hp, h), 0) << hp;
      EXPECT_EQ(IndexInHalfpatchCycle(example.mesh, hp, Twin(h)), -1) << hp;
    }
    const std::vector<BlockId> blocks = BlocksAroundHalfarc(example.mesh, h);
    EXPECT_THAT(blocks, UnorderedElementsAreArray({0, 1, 2, 3}));
  }
}

// The twin's halfpatches are the arc's list reversed with every side flipped, so both halfarcs
// see the same radial order from their own direction.
TEST(HalfarcNeighborhoodTest, TheTwinSeesTheRadialOrderReversedAndFlipped) {
  const Example example = Build(Step());
  for (ArcId a = 0; a < example.mesh.num_arcs(); ++a) {
    const std::vector<HalfpatchId> forward = HalfpatchesAroundHalfarc(example.mesh, 2 * a);
    const std::span<const HalfpatchId> listed = example.mesh.arc_halfpatches(a);
    EXPECT_TRUE(std::equal(forward.begin(), forward.end(), listed.begin(), listed.end()));
    std::vector<HalfpatchId> backward = HalfpatchesAroundHalfarc(example.mesh, 2 * a + 1);
    std::reverse(backward.begin(), backward.end());
    for (HalfpatchId& hp : backward) hp ^= 1;
    EXPECT_EQ(backward, forward) << "arc " << a;
    for (HalfpatchId hp : HalfpatchesAroundHalfarc(example.mesh, 2 * a + 1)) {
      EXPECT_GE(IndexInHalfpatchCycle(example.mesh, hp, 2 * a + 1), 0);
    }
  }
}

// Blocks come in radial order, each once, boundary sides skipped; the in-place overload clears
// what it is given and agrees with the allocating one.
TEST(HalfarcNeighborhoodTest, BlocksFollowTheRadialOrderOnceEachWithoutBoundarySides) {
  const Example example = Build(Step());
  std::vector<BlockId> reused = {7, 7, 7};
  for (HalfarcId h = 0; h < example.mesh.num_halfarcs(); ++h) {
    std::vector<BlockId> expected;
    for (HalfpatchId hp : HalfpatchesAroundHalfarc(example.mesh, h)) {
      const BlockId b = example.mesh.halfpatch_block(hp);
      if (b != kNoId && std::find(expected.begin(), expected.end(), b) == expected.end()) {
        expected.push_back(b);
      }
    }
    EXPECT_EQ(BlocksAroundHalfarc(example.mesh, h), expected) << h;
    BlocksAroundHalfarc(example.mesh, h, &reused);
    EXPECT_EQ(reused, expected) << h;
    if (h % 2 == 0) {
      const std::span<const BlockId> arc_blocks = example.mesh.arc_blocks(ArcOf(h));
      EXPECT_TRUE(
          std::equal(expected.begin(), expected.end(), arc_blocks.begin(), arc_blocks.end()));
    }
  }
  // The concave edge: both blocks; a convex edge of the tall block: that block alone.
  const ArcId concave = example.grid.ArcBetween({1, 0, 1}, {1, 1, 1});
  const ArcId convex = example.grid.ArcBetween({0, 0, 0}, {0, 1, 0});
  EXPECT_THAT(BlocksAroundHalfarc(example.mesh, 2 * concave), UnorderedElementsAreArray({0, 1}));
  EXPECT_EQ(BlocksAroundHalfarc(example.mesh, 2 * convex + 1), std::vector<BlockId>{0});
}

// Next and previous walk the halfpatch's closed cycle, also across T-junctions and on the twin
// side, whose cycle is the reversed list.
TEST(HalfarcNeighborhoodTest, NextAndPreviousWalkTheClosedCycle) {
  const Example example = Build(Step());
  const TMesh& mesh = example.mesh;
  int longer_than_four = 0;
  for (HalfpatchId hp = 0; hp < mesh.num_halfpatches(); ++hp) {
    const int size = mesh.halfpatch_cycle_size(hp);
    longer_than_four += size > 4 ? 1 : 0;
    for (int i = 0; i < size; ++i) {
      const HalfarcId h = mesh.HalfpatchCycleAt(hp, i);
      EXPECT_EQ(IndexInHalfpatchCycle(mesh, hp, h), i);
      const HalfarcId next = NextInHalfpatch(mesh, hp, h);
      const HalfarcId prev = PrevInHalfpatch(mesh, hp, h);
      EXPECT_EQ(next, mesh.HalfpatchCycleAt(hp, (i + 1) % size));
      EXPECT_EQ(mesh.tail(next), mesh.head(h));
      EXPECT_EQ(mesh.head(prev), mesh.tail(h));
      EXPECT_EQ(PrevInHalfpatch(mesh, hp, next), h);
    }
  }
  EXPECT_GT(longer_than_four, 0);
}

// A boundary side has no block; its halfarc directions are read in the block across the patch.
TEST(HalfarcNeighborhoodTest, ABoundarySideIsReadInTheBlockAcrossThePatch) {
  const Example example = Build(Step());
  const TMesh& mesh = example.mesh;
  const PatchId bottom = example.grid.PatchAt({{1, 0, 0}, {2, 1, 0}});
  const PatchId wall = example.grid.PatchAt({{1, 0, 0}, {1, 1, 1}});
  ASSERT_GE(bottom, 0);
  ASSERT_GE(wall, 0);
  for (int side = 0; side < 2; ++side) {
    EXPECT_EQ(FrameBlockOfHalfpatch(mesh, 2 * bottom + side), 1);
    EXPECT_EQ(FrameBlockOfHalfpatch(mesh, 2 * wall + side), mesh.patch_block(wall, side));
  }
  EXPECT_NE(mesh.patch_block(wall, 0), mesh.patch_block(wall, 1));
}

}  // namespace
}  // namespace ispq
