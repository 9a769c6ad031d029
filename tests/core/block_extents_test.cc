// SPDX-License-Identifier: Apache-2.0
// T2 of core/README.md, section Cases with known answers: the hex count of a quantization, and
// the extent rows.
#include "core/block_extents.h"

#include <array>
#include <vector>

#include "gtest/gtest.h"
#include "tests/support/grid_tmesh_builder.h"
#include "tests/support/test_data.h"

namespace ispq {
namespace {

using ::ispq::testing::BuildGridTMesh;
using ::ispq::testing::GridTMesh;
using ::ispq::testing::GridTMeshSpec;
using ::ispq::testing::TMeshOrDie;

TEST(BlockExtentsTest, HexCount) {
  GridTMeshSpec two;
  two.blocks = {{{0, 0, 0}, {1, 1, 1}}, {{1, 0, 0}, {2, 1, 1}}};
  const absl::StatusOr<GridTMesh> grid = BuildGridTMesh(two);
  ASSERT_TRUE(grid.ok()) << grid.status();
  const TMesh mesh = TMeshOrDie(grid->proto());
  const std::vector<int64_t> q = grid->QFromIntervals({{{2, 3}, {4}, {5}}});
  EXPECT_EQ(HexCount(mesh, q), std::optional<int64_t>(2 * 4 * 5 + 3 * 4 * 5));
  for (BlockId b = 0; b < 2; ++b) {
    EXPECT_EQ(BlockExtent(mesh, b, 0, q), b == 0 ? 2 : 3);
    EXPECT_EQ(BlockExtent(mesh, b, 1, q), 4);
    EXPECT_EQ(BlockExtent(mesh, b, 2, q), 5);
  }

  GridTMeshSpec cube;
  cube.blocks = {{{0, 0, 0}, {1, 1, 1}}};
  const absl::StatusOr<GridTMesh> cube_grid = BuildGridTMesh(cube);
  ASSERT_TRUE(cube_grid.ok()) << cube_grid.status();
  const TMesh cube_mesh = TMeshOrDie(cube_grid->proto());
  EXPECT_EQ(HexCount(cube_mesh, cube_grid->QFromIntervals({{{1}, {1}, {1}}})),
            std::optional<int64_t>(1));
  EXPECT_EQ(HexCount(cube_mesh, cube_grid->QFromIntervals({{{0}, {1}, {1}}})),
            std::optional<int64_t>(0));
}

}  // namespace
}  // namespace ispq
