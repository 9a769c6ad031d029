// SPDX-License-Identifier: Apache-2.0
// The parallel classes (core/parallel_classes.h): one per global axis on a grid whose blocks are
// rotated against each other, and on every real T-mesh an arc's class read in any block around it.
#include "core/parallel_classes.h"

#include <set>
#include <string>
#include <vector>

#include "gtest/gtest.h"
#include "tests/support/grid_tmesh_builder.h"
#include "tests/support/test_data.h"

namespace ispq {
namespace {

using ::ispq::testing::BuildGridTMesh;
using ::ispq::testing::GridTMesh;
using ::ispq::testing::GridTMeshSpec;
using ::ispq::testing::LoadTMeshOrDie;
using ::ispq::testing::RealTMeshFiles;
using ::ispq::testing::ShortName;
using ::ispq::testing::TMeshOrDie;

// The axis along which an arc of the grid runs (its ends differ there).
int GlobalAxis(const GridTMesh& grid, ArcId a) {
  const auto& [from, to] = grid.arc_ends(a);
  for (int axis = 0; axis < 3; ++axis) {
    if (from[axis] != to[axis]) return axis;
  }
  return -1;
}

// Every block around an arc puts the arc in the class the arc has.
void ExpectArcClassesAgreeWithEveryBlock(const TMesh& mesh, const ParallelClasses& classes) {
  for (ArcId a = 0; a < mesh.num_arcs(); ++a) {
    for (BlockId b : mesh.arc_blocks(a)) {
      const std::optional<Dir> dir = mesh.HalfarcDirInBlock(HalfarcOf(a, false), b);
      ASSERT_TRUE(dir.has_value());
      EXPECT_EQ(classes.of_block_axis(b, AxisOf(*dir)), classes.of_arc(a))
          << "arc " << a << " in block " << b;
    }
  }
}

// Three blocks in a row and one on top, two of them in rotated frames: each global axis is one
// class, whatever axis it is in each block's own frame.
TEST(ParallelClassesTest, OneClassPerGlobalAxisAcrossRotatedBlocks) {
  GridTMeshSpec spec;
  spec.blocks = {{{0, 0, 0}, {1, 1, 1}},
                 {{1, 0, 0}, {2, 1, 1}},
                 {{2, 0, 0}, {3, 1, 1}},
                 {{0, 0, 1}, {3, 1, 2}}};
  spec.block_rotations = {{1, 5}, {3, 17}};
  const absl::StatusOr<GridTMesh> grid = BuildGridTMesh(spec);
  ASSERT_TRUE(grid.ok()) << grid.status();
  const TMesh mesh = TMeshOrDie(grid->proto());
  const ParallelClasses classes(mesh);

  EXPECT_EQ(classes.num_classes(), 3);
  std::vector<std::set<int32_t>> classes_along(3);
  for (ArcId a = 0; a < mesh.num_arcs(); ++a) {
    classes_along[GlobalAxis(*grid, a)].insert(classes.of_arc(a));
  }
  for (int axis = 0; axis < 3; ++axis) {
    SCOPED_TRACE(axis);
    ASSERT_EQ(classes_along[axis].size(), 1u);
    for (int other = 0; other < axis; ++other) {
      EXPECT_NE(*classes_along[axis].begin(), *classes_along[other].begin());
    }
  }
  ExpectArcClassesAgreeWithEveryBlock(mesh, classes);
}

// The search's bound relies on this on every mesh: with singular arcs the rotations around them
// join classes, never split an arc's.
TEST(ParallelClassesTest, RealMeshesGiveEachArcOneClass) {
  const std::vector<std::string> files = RealTMeshFiles();
  ASSERT_FALSE(files.empty());
  int with_fewer_than_three = 0;
  for (const std::string& file : files) {
    SCOPED_TRACE(ShortName(file));
    const TMesh mesh = LoadTMeshOrDie(file);
    const ParallelClasses classes(mesh);
    EXPECT_GE(classes.num_classes(), 1);
    EXPECT_LE(classes.num_classes(), 3);
    if (classes.num_classes() < 3) ++with_fewer_than_three;
    ExpectArcClassesAgreeWithEveryBlock(mesh, classes);
  }
  EXPECT_GT(with_fewer_than_three, 0) << "some real meshes have singular arcs";
}

}  // namespace
}  // namespace ispq
